// SPDX-License-Identifier: GPL-2.0-or-later
// Reprojection residuals of views through a solution, and the noise they
// and the PnP fits show.
#include "residuals.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "detection_noise.h"

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

namespace {

/// A view's detection noise σ per axis from its PnP fit (n points, 2n − 6
/// degrees of freedom); nullopt where it has too few points to tell.
std::optional<double> ViewSigmaPx(const View& view) {
  const double n = static_cast<double>(view.p_target.size());
  if (!view.used || n <= 3) return std::nullopt;
  return view.pnp_rms_px * std::sqrt(n / (2.0 * n - 6.0));
}

/// The log of the median of per-view σ estimates and its standard error,
/// from their spread (the MAD; a median's variance is π/2 a mean's).
struct LogSigma {
  double log_median = 0;
  double standard_error = 0;
};

LogSigma LogSigmaOf(const std::vector<double>& sigmas) {
  std::vector<double> logs, deviations;
  for (double sigma : sigmas) logs.push_back(std::log(std::max(sigma, 1e-3)));
  const double median = Median(logs);
  for (double l : logs) deviations.push_back(std::abs(l - median));
  const double spread = 1.4826 * Median(std::move(deviations));
  return {median, std::sqrt(M_PI / 2.0) * spread / std::sqrt(static_cast<double>(logs.size()))};
}

/// Fewer views than this and a camera's own σ is too rough to weigh it by.
constexpr size_t kMinViewsForOwnSigma = 3;
/// Standard errors of the difference beyond which a camera's σ is its own.
constexpr double kOwnSigmaStandardErrors = 3.0;

}  // namespace

double MedianSigmaPx(std::vector<double> sigmas) {
  return std::max(Median(std::move(sigmas)), 1e-3);
}

double DetectionSigmaPx(const Problem& problem) {
  std::vector<double> sigmas;
  for (const View& view : problem.views)
    if (const std::optional<double> sigma = ViewSigmaPx(view)) sigmas.push_back(*sigma);
  return MedianSigmaPx(std::move(sigmas));
}

std::vector<double> SigmasApart(const std::vector<std::vector<double>>& sigmas) {
  std::vector<double> every, out(sigmas.size(), 0.0);
  for (const std::vector<double>& group : sigmas)
    every.insert(every.end(), group.begin(), group.end());
  if (every.empty()) return out;
  const LogSigma pooled = LogSigmaOf(every);
  for (size_t k = 0; k < sigmas.size(); ++k) {
    if (sigmas[k].size() < kMinViewsForOwnSigma) continue;
    const LogSigma own = LogSigmaOf(sigmas[k]);
    const double error = std::hypot(own.standard_error, pooled.standard_error);
    if (std::abs(own.log_median - pooled.log_median) > kOwnSigmaStandardErrors * error)
      out[k] = MedianSigmaPx(sigmas[k]);
  }
  return out;
}

std::vector<double> CameraSigmasPx(const Problem& problem) {
  std::vector<std::vector<double>> sigmas(problem.dataset->cameras.size());
  for (const View& view : problem.views)
    if (const std::optional<double> sigma = ViewSigmaPx(view))
      sigmas[view.camera].push_back(*sigma);
  const double all = DetectionSigmaPx(problem);
  std::vector<double> out = SigmasApart(sigmas);
  for (double& sigma : out)
    if (sigma == 0) sigma = all;
  return out;
}

std::vector<double> CameraWeights(const Problem& problem) {
  const double all = DetectionSigmaPx(problem);
  std::vector<double> weight;
  for (double sigma : CameraSigmasPx(problem)) weight.push_back(all / sigma);
  return weight;
}

}  // namespace handeye::internal
