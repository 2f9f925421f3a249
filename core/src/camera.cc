// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/camera.h"

#include <Eigen/LU>
#include <ceres/jet.h>

namespace handeye {

std::optional<Camera> Camera::Make(std::string name, int width, int height, double fx, double fy,
                                   double cx, double cy, const std::vector<double>& distortion,
                                   std::string* why) {
  auto fail = [why](const std::string& reason) -> std::optional<Camera> {
    if (why) *why = reason;
    return std::nullopt;
  };
  const size_t n = distortion.size();
  if (n != 0 && n != 4 && n != 5 && n != 8 && n != 12 && n != 14)
    return fail("0, 4, 5, 8, 12 or 14 distortion coefficients (OpenCV order), got " +
                std::to_string(n));
  if (width <= 0 || height <= 0) return fail("a positive image size");
  if (!std::isfinite(fx) || !std::isfinite(fy) || fx <= 0 || fy <= 0)
    return fail("positive, finite focal lengths fx and fy");
  if (!std::isfinite(cx) || !std::isfinite(cy)) return fail("finite principal point cx, cy");
  for (double k : distortion)
    if (!std::isfinite(k)) return fail("finite distortion coefficients");
  Camera cam;
  cam.name = std::move(name);
  cam.width = width;
  cam.height = height;
  cam.params = {};
  cam.params[0] = fx;
  cam.params[1] = fy;
  cam.params[2] = cx;
  cam.params[3] = cy;
  for (size_t i = 0; i < n; ++i) cam.params[4 + i] = distortion[i];
  cam.num_distortion = static_cast<int>(n);
  return cam;
}

std::vector<double> Camera::Distortion() const {
  return std::vector<double>(params.begin() + 4, params.begin() + 4 + num_distortion);
}

const char* Camera::ParamName(int index) {
  static const char* const kNames[OpenCVCameraModel::kNumParams] = {
      "fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6", "s1", "s2", "s3", "s4", "tau_x", "tau_y"};
  return index >= 0 && index < OpenCVCameraModel::kNumParams ? kNames[index] : "?";
}

bool Camera::HasDistortion() const {
  for (int i = 4; i < OpenCVCameraModel::kNumParams; ++i)
    if (params[i] != 0.0) return true;
  return false;
}

std::optional<Eigen::Vector2d> Camera::Project(const Eigen::Vector3d& p_cam) const {
  Eigen::Vector2d uv;
  if (!OpenCVCameraModel::Project(params.data(), p_cam.data(), uv.data())) return std::nullopt;
  return uv;
}

std::optional<Eigen::Vector2d> Camera::Undistort(const Eigen::Vector2d& uv) const {
  const Eigen::Vector2d target((uv.x() - cx()) / fx(), (uv.y() - cy()) / fy());
  if (!HasDistortion()) return target;
  using Jet = ceres::Jet<double, 2>;
  std::array<Jet, OpenCVCameraModel::kNumParams> jet_params;
  for (int i = 0; i < OpenCVCameraModel::kNumParams; ++i) jet_params[i] = Jet(params[i]);
  Eigen::Vector2d x = target;
  for (int iter = 0; iter < 50; ++iter) {
    const Jet jx(x.x(), 0), jy(x.y(), 1);
    Jet xd, yd;
    OpenCVCameraModel::Distort(jet_params.data(), jx, jy, &xd, &yd);
    const Eigen::Vector2d r(xd.a - target.x(), yd.a - target.y());
    if (!r.allFinite()) return std::nullopt;
    if (r.norm() < 1e-14) return x;
    Eigen::Matrix2d J;
    J << xd.v[0], xd.v[1], yd.v[0], yd.v[1];
    const Eigen::Vector2d step = J.partialPivLu().solve(r);
    if (!step.allFinite()) return std::nullopt;
    x -= step;
  }
  // Accept a residual that is tiny in pixels even if not below 1e-14.
  Jet xd, yd;
  OpenCVCameraModel::Distort(jet_params.data(), Jet(x.x()), Jet(x.y()), &xd, &yd);
  const Eigen::Vector2d r(xd.a - target.x(), yd.a - target.y());
  if (r.allFinite() && r.norm() * std::max(fx(), fy()) < 1e-9) return x;
  return std::nullopt;
}

}  // namespace handeye
