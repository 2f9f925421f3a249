// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Where a ChArUco board's markers are: OpenCV's board object laid out as the
// target declares (OpenCV 4.6 can only make its own layout), and, when a view
// fails, whether the markers seen fit another layout than the declared one.
// Internal to the detectors library.

#include <memory>
#include <opencv2/aruco/charuco.hpp>
#include <string>
#include <utility>
#include <vector>

#include "handeye/core/charuco.h"

namespace handeye::internal {

/// Puts the markers of `target` into `board`, made by CharucoBoard::create
/// for the same squares with squares of side 1: each marker's corners and,
/// for each chessboard corner, its two markers and their nearest corners
/// (what interpolateCornersCharuco reads). create() gives OpenCV 4.6's layout;
/// this moves the markers where a legacy layout has them.
void LayOutMarkers(const CharucoTarget& target, cv::aruco::CharucoBoard* board);

/// Fraction of the markers (ids and image corners, as detectMarkers gives
/// them) whose four corners one homography of `target`'s marker corners
/// onto the image puts within a fifth of a marker side (RANSAC).
double LayoutFit(const CharucoTarget& target, const std::vector<int>& ids,
                 const std::vector<std::vector<cv::Point2f>>& corners);

/// The layouts a print of `target` may have instead of the declared one (the
/// other OpenCV layout where sy is even, the transposed squares, both), each
/// with the sentence that tells the user what to change.
std::vector<std::pair<std::shared_ptr<const CharucoTarget>, std::string>> OtherLayouts(
    const CharucoTarget& target);

}  // namespace handeye::internal
