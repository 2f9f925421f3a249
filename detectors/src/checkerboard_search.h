// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Where the checkerboard detector looks for the board: OpenCV's sector
// detector run coarse to fine, in crops before whole images. Internal to the
// detectors library.

#include <opencv2/core.hpp>
#include <optional>

#include "checkerboard_grid.h"

namespace handeye::internal {

/// The full grid of `cols` x `rows` inner corners in `gray` (8-bit, single
/// channel), refined and verified (RefineGrid), in the order OpenCV lists
/// them; nullopt when there is none.
std::optional<Grid> FindGrid(const cv::Mat& gray, int cols, int rows);

}  // namespace handeye::internal
