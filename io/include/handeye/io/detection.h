// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Target detection over a whole dataset, in parallel (`handeye detect`).

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "handeye/core/dataset.h"
#include "handeye/core/warning.h"

namespace handeye {

/// How DetectAll() runs.
struct DetectOptions {
  /// Worker threads; 0 = all cores.
  int threads = 0;
  /// Called after each image with (done, total), from one thread at a time.
  std::function<void(std::size_t, std::size_t)> progress;
};

/// Runs the target's detector on every image of the dataset, streaming the
/// images (at most one per thread in memory), and replaces
/// dataset->observations with what was found, in pose then camera order.
/// Throws InputError for an image that is missing, unreadable or of the wrong size.
/// Returns warnings for the user: images where the detector saw the target
/// declared differently (Detector::DetectOrExplain), one warning per
/// difference, with how many images showed it.
std::vector<Warning> DetectAll(Dataset* dataset, const DetectOptions& options = {});

}  // namespace handeye
