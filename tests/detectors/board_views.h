// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Helpers for the detector tests: cameras, board poses with known truth and
/// the true pixels of every corner.

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "handeye/core/camera.h"
#include "handeye/core/checkerboard.h"

namespace handeye::test {

/// A camera with principal point near the image centre (slightly off, so no
/// symmetry hides a convention error).
inline Camera MakeTestCamera(int width, int height, double f,
                             const std::vector<double>& distortion) {
  std::string why;
  auto camera = Camera::Make("cam0", width, height, f, f * 1.0004, width / 2.0 - 0.37,
                             height / 2.0 + 0.61, distortion, &why);
  if (!camera) throw std::runtime_error("test camera: " + why);
  return *camera;
}

/// Some lens distortion (k1, k2, p1, p2, k3): with f = 0.9 × width it moves
/// the image corners by about 20 px.
inline std::vector<double> MildDistortion() { return {-0.08, 0.03, 4e-4, -3e-4, 0.0}; }

/// T_cam_target that shows the board's corner grid centred on the normalised
/// image point (x, y) at `distance_m`, turned by `in_plane_rad` about the
/// optical axis and tilted by `tilt_rad` about the in-plane `tilt_axis`. The
/// camera sees the printed face (target +z points away from it).
inline Eigen::Isometry3d BoardPose(const CheckerboardTarget& board, double distance_m,
                                   double in_plane_rad, double tilt_rad,
                                   const Eigen::Vector2d& tilt_axis, const Eigen::Vector2d& xy) {
  const Eigen::Vector3d axis(tilt_axis.x(), tilt_axis.y(), 0.0);
  const Eigen::Matrix3d R_cam_target = (Eigen::AngleAxisd(tilt_rad, axis.normalized()) *
                                        Eigen::AngleAxisd(in_plane_rad, Eigen::Vector3d::UnitZ()))
                                           .toRotationMatrix();
  const double s = board.square_size_m();
  const Eigen::Vector3d centre_target((board.cols() - 1) * s / 2, (board.rows() - 1) * s / 2, 0);
  Eigen::Isometry3d T_cam_target = Eigen::Isometry3d::Identity();
  T_cam_target.linear() = R_cam_target;
  T_cam_target.translation() =
      Eigen::Vector3d(xy.x() * distance_m, xy.y() * distance_m, distance_m) -
      R_cam_target * centre_target;
  return T_cam_target;
}

/// True pixel of every target point (ordered by id), by Camera::Project.
inline std::vector<Eigen::Vector2d> TruePixels(const Camera& camera, const Target& target,
                                               const Eigen::Isometry3d& T_cam_target) {
  std::vector<Eigen::Vector2d> px;
  for (const auto& p : target.Points()) px.push_back(*camera.Project(T_cam_target * p.p_target));
  return px;
}

/// True when the whole printed sheet (Target::Extent) projects at least
/// `margin` px inside the image.
inline bool SheetInImage(const Camera& camera, const Target& target,
                         const Eigen::Isometry3d& T_cam_target, double margin) {
  const Eigen::AlignedBox2d e = target.Extent();
  for (int k = 0; k <= 40; ++k) {
    const double s = k / 40.0;
    const Eigen::Vector2d pts[4] = {{e.min().x() + s * e.sizes().x(), e.min().y()},
                                    {e.min().x() + s * e.sizes().x(), e.max().y()},
                                    {e.min().x(), e.min().y() + s * e.sizes().y()},
                                    {e.max().x(), e.min().y() + s * e.sizes().y()}};
    for (const auto& p : pts) {
      const auto uv = camera.Project(T_cam_target * Eigen::Vector3d(p.x(), p.y(), 0));
      if (!uv || !camera.InImage(*uv, margin)) return false;
    }
  }
  return true;
}

}  // namespace handeye::test
