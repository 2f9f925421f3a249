// SPDX-License-Identifier: GPL-2.0-or-later
// Reprojection residuals of views through a solution, and the noise they
// and the PnP fits show.
#include "residuals.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace handeye::internal {
namespace {

/// Residual norms (pixels) of every point of a used view through the chain.
std::vector<double> PointErrors(const Problem& problem,
                                const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                                const TargetPoses& T_holder_target) {
  std::vector<double> errors;
  for (const View& view : problem.views) {
    if (!view.used || !T_cam_mount[view.camera]) continue;
    const auto e =
        ViewErrors(problem, view, *T_cam_mount[view.camera], T_holder_target[view.camera]);
    errors.insert(errors.end(), e.begin(), e.end());
  }
  return errors;
}

}  // namespace

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

std::vector<double> ViewErrors(const Problem& problem, const View& view,
                               const Eigen::Isometry3d& T_cam_mount,
                               const Eigen::Isometry3d& T_holder_target) {
  const Camera& camera = problem.dataset->cameras[view.camera];
  const Eigen::Isometry3d T_cam_target =
      T_cam_mount * problem.T_mount_holder[view.pose] * T_holder_target;
  std::vector<double> errors;
  for (size_t i = 0; i < view.p_target.size(); ++i) {
    const auto uv = camera.Project(T_cam_target * view.p_target[i]);
    errors.push_back(uv ? (*uv - view.observation->points_px[i]).norm() : 1e6);
  }
  return errors;
}

double ViewRms(const std::vector<double>& errors, double* max_error) {
  double sum = 0, largest = 0;
  for (double e : errors) {
    sum += e * e;
    largest = std::max(largest, e);
  }
  if (max_error) *max_error = largest;
  return errors.empty() ? 0.0 : std::sqrt(sum / errors.size());
}

double MedianViewRms(const Problem& problem,
                     const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                     const Eigen::Isometry3d& T_holder_target) {
  std::vector<double> rms;
  for (const View& view : problem.views)
    if (view.used && T_cam_mount[view.camera])
      rms.push_back(ViewRms(ViewErrors(problem, view, *T_cam_mount[view.camera], T_holder_target)));
  return rms.empty() ? std::numeric_limits<double>::infinity() : Median(std::move(rms));
}

double ResidualSigmaPx(const Problem& problem,
                       const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                       const TargetPoses& T_holder_target) {
  // The norm of a 2D Gaussian residual of σ per axis has median σ·√(2 ln 2).
  return Median(PointErrors(problem, T_cam_mount, T_holder_target)) /
         std::sqrt(2.0 * std::log(2.0));
}

double DetectionSigmaPx(const Problem& problem) {
  std::vector<double> sigmas;
  for (const View& view : problem.views) {
    const double n = static_cast<double>(view.p_target.size());
    if (view.used && n > 3) sigmas.push_back(view.pnp_rms_px * std::sqrt(n / (2.0 * n - 6.0)));
  }
  return std::max(Median(sigmas), 1e-3);
}

}  // namespace handeye::internal
