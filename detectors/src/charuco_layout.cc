// SPDX-License-Identifier: GPL-2.0-or-later
#include "charuco_layout.h"

#include <algorithm>
#include <opencv2/calib3d.hpp>

namespace handeye::internal {
namespace {

cv::Point3f InSquares(const Eigen::Vector3d& p, double square_m) {
  return cv::Point3f(static_cast<float>(p.x() / square_m), static_cast<float>(p.y() / square_m),
                     0.0f);
}

float SquaredDistance(const cv::Point3f& a, const cv::Point3f& b) {
  const cv::Point3f d = a - b;
  return d.x * d.x + d.y * d.y;
}

/// `target` with `squares` and `layout` replaced.
std::shared_ptr<const CharucoTarget> Variant(const CharucoTarget& target, int sx, int sy,
                                             bool legacy) {
  TargetSpec spec = target.Spec();
  spec.values["squares"] = std::vector<double>{static_cast<double>(sx), static_cast<double>(sy)};
  spec.values["layout"] = std::string(legacy ? "legacy" : "opencv");
  return std::make_shared<const CharucoTarget>(spec, target.dictionary());
}

}  // namespace

void LayOutMarkers(const CharucoTarget& target, cv::aruco::CharucoBoard* board) {
  const double L = target.square_size_m();
  const int markers = target.NumMarkers();
  board->objPoints.assign(static_cast<std::size_t>(markers), {});
  for (int k = 0; k < markers; ++k)
    for (const Eigen::Vector3d& p : target.MarkerCorners(k))
      board->objPoints[k].push_back(InSquares(p, L));
  const std::size_t corners = target.Points().size();
  board->nearestMarkerIdx.assign(corners, {});
  board->nearestMarkerCorners.assign(corners, {});
  for (std::size_t c = 0; c < corners; ++c) {
    const cv::Point3f corner = InSquares(target.Points()[c].p_target, L);
    // The two markers touching the corner are its nearest (the other two
    // squares there are black); of each, the marker corner nearest to it.
    for (const int marker : target.MarkersAtCorner(static_cast<int>(c))) {
      const std::vector<cv::Point3f>& q = board->objPoints[marker];
      int nearest = 0;
      for (int k = 1; k < 4; ++k)
        if (SquaredDistance(q[k], corner) < SquaredDistance(q[nearest], corner)) nearest = k;
      board->nearestMarkerIdx[c].push_back(marker);
      board->nearestMarkerCorners[c].push_back(nearest);
    }
  }
}

double LayoutFit(const CharucoTarget& target, const std::vector<int>& ids,
                 const std::vector<std::vector<cv::Point2f>>& corners) {
  std::vector<cv::Point2f> board_xy, image_uv;
  std::vector<double> sides;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] < 0 || ids[i] >= target.NumMarkers()) continue;
    const auto object = target.MarkerCorners(ids[i]);
    for (int k = 0; k < 4; ++k) {
      board_xy.emplace_back(static_cast<float>(object[k].x()), static_cast<float>(object[k].y()));
      image_uv.push_back(corners[i][k]);
    }
    sides.push_back(cv::norm(corners[i][1] - corners[i][0]));
  }
  if (sides.size() < 4) return 0.0;
  std::nth_element(sides.begin(), sides.begin() + sides.size() / 2, sides.end());
  const double tolerance_px = std::max(1.0, 0.2 * sides[sides.size() / 2]);
  std::vector<std::uint8_t> inlier;
  const cv::Mat H = cv::findHomography(board_xy, image_uv, cv::RANSAC, tolerance_px, inlier);
  if (H.empty()) return 0.0;
  int fitting = 0;
  for (std::size_t m = 0; m < sides.size(); ++m)
    fitting += inlier[4 * m] && inlier[4 * m + 1] && inlier[4 * m + 2] && inlier[4 * m + 3];
  return static_cast<double>(fitting) / static_cast<double>(sides.size());
}

std::vector<std::pair<std::shared_ptr<const CharucoTarget>, std::string>> OtherLayouts(
    const CharucoTarget& target) {
  const int sx = target.squares_x(), sy = target.squares_y();
  const bool legacy = target.legacy();
  const std::string squares = "[" + std::to_string(sx) + ", " + std::to_string(sy) + "]";
  const std::string swapped = "[" + std::to_string(sy) + ", " + std::to_string(sx) + "]";
  std::vector<std::pair<std::shared_ptr<const CharucoTarget>, std::string>> layouts;
  // OpenCV's two layouts differ only where the row count is even.
  if (sy % 2 == 0)
    layouts.emplace_back(
        Variant(target, sx, sy, !legacy),
        legacy
            ? "the ChArUco board in the images is laid out as OpenCV 4.6 and later print it; the "
              "target declares \"layout\": \"legacy\": remove it"
            : "the ChArUco board in the images is an old-style print (OpenCV before 4.6: with an "
              "even number of rows square (0, 0) is white and the markers sit in the other "
              "squares); the target declares OpenCV 4.6's layout: add \"layout\": \"legacy\" to "
              "the target");
  if (sx != sy) {
    const std::string transposed =
        "the ChArUco board in the images has " + std::to_string(sy) + "x" + std::to_string(sx) +
        " squares; the target declares squares " + squares + ": swap it to " + swapped;
    layouts.emplace_back(Variant(target, sy, sx, legacy), transposed);
    // Transposed, the row count is sx.
    if (sx % 2 == 0)
      layouts.emplace_back(Variant(target, sy, sx, !legacy),
                           transposed + (legacy ? " and remove \"layout\": \"legacy\""
                                                : " and add \"layout\": \"legacy\" (an old-style "
                                                  "print, OpenCV before 4.6)"));
  }
  return layouts;
}

}  // namespace handeye::internal
