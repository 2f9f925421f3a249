// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Image files a dataset lists for several robot poses of one camera: the same
/// path, or files with the same bytes (issue 28: every pose listing one image
/// calibrated with exit 0, cameras 41 m off).

#include <string>
#include <vector>

#include "handeye/core/dataset.h"
#include "handeye/core/warning.h"

namespace handeye {

/// One warning per group of a camera's poses whose images are the same file
/// or byte-identical files, naming the poses and the files. Reads only what
/// it must: files are compared by size first, then by their first 64 KiB,
/// and only those alike so far are read whole. Files that cannot be read are
/// skipped (detection reports them). Calibrate() leaves such views out (their
/// detected points are identical) and fails when they are a third of the views.
std::vector<Warning> RepeatedImageWarnings(const Dataset& dataset);

}  // namespace handeye
