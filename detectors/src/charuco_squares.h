// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A ChArUco board numbered from its black squares when its markers are too
// small to decode: seen obliquely from a cell camera's distance a marker's
// bits are a pixel or less across the tilt, but the black squares are still
// dark quadrilaterals touching at their corners, and the markers' grey
// levels, taken together, still say which way round the board lies.
// Internal to the detectors library.

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "handeye/core/charuco.h"

namespace handeye::internal {

/// One inner corner of the board placed by the black squares: where to look
/// for it and the homography of the squares around it (board metres to
/// pixels), for CharucoDetector::RefineCorner.
struct PlacedCorner {
  int id = 0;
  Eigen::Vector2d guess_px;
  Eigen::Matrix3d H_image_target;
};

/// The inner corners of `target` numbered from the quadrilaterals `quads`
/// (cv::aruco::detectMarkers' rejected candidates: the black squares among
/// them): the squares that touch corner to corner are joined into a lattice,
/// every way the lattice fits the board's black squares is tried, and the
/// one under which the image's grey levels at the markers' bits follow the
/// print clearly best numbers the corners. Markers already decoded
/// (`marker_ids`, `marker_corners`) must lie where that placement puts them.
/// How far ahead of any other the best placement's correlation must be; and
/// the placement on the declared board ahead of those on the other layouts a
/// print may have (internal::OtherLayouts).
constexpr double kMinLead = 0.15;

struct SquaresPlacement {
  /// Empty when no placement stands out.
  std::vector<PlacedCorner> corners;
  /// The best placement's correlation with the print; -1 without a lattice
  /// or a placement.
  double correlation = -1;
  /// Squares of the lattice the best placement puts on no black square of
  /// the board (clutter joined in, or a print whose squares lie otherwise).
  int misfits = 0;
};
SquaresPlacement PlaceCornersBySquares(const CharucoTarget& target, const cv::Mat& gray,
                                       const std::vector<std::vector<cv::Point2f>>& quads,
                                       const std::vector<int>& marker_ids,
                                       const std::vector<std::vector<cv::Point2f>>& marker_corners);

}  // namespace handeye::internal
