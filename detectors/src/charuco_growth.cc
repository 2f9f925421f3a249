// SPDX-License-Identifier: GPL-2.0-or-later
#include "charuco_growth.h"

#include "corner_refinement.h"

namespace handeye::internal {
namespace {

/// Known points farther than this many squares from a corner (along either
/// board axis) do not predict it: a homography of nearby points only, so
/// that lens distortion across the board does not bend the prediction.
constexpr double kSupportSquares = 2.0;
/// Fewest known points whose homography predicts a corner (four would fit
/// any four points exactly).
constexpr std::size_t kMinSupport = 5;
/// A decoded marker agrees with the others when its corners, taken back onto
/// the board by the homography of all the markers, lie on average within
/// this many squares of where it is printed. Another marker of the board is
/// printed at least one square away along each axis (white squares alternate),
/// so a misread marker lies a square or more off.
constexpr double kMarkerAgreementSquares = 0.4;

}  // namespace

std::vector<std::pair<int, Eigen::Vector2d>> GrowCharucoCorners(
    const CharucoTarget& target, const std::vector<int>& marker_ids,
    const std::vector<std::vector<cv::Point2f>>& marker_corners,
    const std::vector<std::pair<int, Eigen::Vector2d>>& found, const CharucoCornerRefiner& refine) {
  std::vector<std::pair<int, Eigen::Vector2d>> added;
  if (static_cast<int>(marker_ids.size()) < kMinGrowthMarkers) return added;
  const double L = target.square_size_m();
  // Known points: on the board (metres) and in the image (pixels).
  std::vector<Eigen::Vector2d> known_xy, known_px;
  for (std::size_t i = 0; i < marker_ids.size(); ++i) {
    const auto object = target.MarkerCorners(marker_ids[i]);
    for (int k = 0; k < 4; ++k) {
      known_xy.push_back(object[k].head<2>());
      known_px.emplace_back(marker_corners[i][k].x, marker_corners[i][k].y);
    }
  }
  const auto H_all = FitHomography(known_xy, known_px);
  if (!H_all) return added;
  const Eigen::Matrix3d target_from_image = H_all->inverse();
  for (std::size_t k = 0; k < known_xy.size(); k += 4) {
    double off_m = 0;
    for (std::size_t c = k; c < k + 4; ++c)
      off_m += (ApplyHomography(target_from_image, known_px[c]) - known_xy[c]).norm() / 4;
    if (off_m > kMarkerAgreementSquares * L) return added;
  }

  const int num_corners = static_cast<int>(target.Points().size());
  std::vector<char> known(static_cast<std::size_t>(num_corners), 0);
  for (const auto& [id, px] : found) {
    known[static_cast<std::size_t>(id)] = 1;
    known_xy.push_back(target.FindPoint(id)->p_target.head<2>());
    known_px.push_back(px);
  }
  // A corner is tried again only once more known points surround it.
  std::vector<std::size_t> tried_with(known.size(), 0);
  for (bool grew = true; grew;) {
    grew = false;
    for (int id = 0; id < num_corners; ++id) {
      if (known[static_cast<std::size_t>(id)]) continue;
      const Eigen::Vector2d xy = target.FindPoint(id)->p_target.head<2>();
      std::vector<Eigen::Vector2d> near_xy, near_px;
      for (std::size_t k = 0; k < known_xy.size(); ++k) {
        if ((known_xy[k] - xy).cwiseAbs().maxCoeff() > kSupportSquares * L * (1 + 1e-9)) continue;
        near_xy.push_back(known_xy[k]);
        near_px.push_back(known_px[k]);
      }
      if (near_xy.size() < kMinSupport || near_xy.size() <= tried_with[id]) continue;
      tried_with[id] = near_xy.size();
      const auto H = FitHomography(near_xy, near_px);
      if (!H) continue;
      const auto refined = refine(id, *H, ApplyHomography(*H, xy));
      if (!refined) continue;
      known[static_cast<std::size_t>(id)] = 1;
      known_xy.push_back(xy);
      known_px.push_back(*refined);
      added.emplace_back(id, *refined);
      grew = true;
    }
  }
  return added;
}

}  // namespace handeye::internal
