// SPDX-License-Identifier: GPL-2.0-or-later
// The robot's own pose error σ, re-estimated from a solve that modelled it:
// one expectation-maximisation step over the robot pose blocks.
#include <cmath>

#include "calibration_internal.h"
#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"

namespace handeye::internal {
namespace {

/// A perturbation of the flange pose in the prior's coordinates: a turn ω
/// about the base frame's axes through the flange (R → exp(ω)·R) and a shift
/// δt of the flange position, both in the base frame.
Eigen::Isometry3d Perturbed(const Eigen::Isometry3d& T_base_ee, const Eigen::Matrix<double, 6, 1>& delta) {
  Eigen::Isometry3d T = T_base_ee;
  T.linear() = MatrixFromRotationVector(delta.head<3>()) * T_base_ee.linear();
  T.translation() += delta.tail<3>();
  return T;
}

/// How well a pose's views alone locate its flange, given the solved camera
/// and target transforms: the
/// information matrix Σ JᵀJ / σ² of the views' points with respect to the
/// perturbation above (central differences; 6 × 2 projections per point).
Eigen::Matrix<double, 6, 6> FlangeInformation(const Problem& problem, const Refinement& solved, int pose,
                                              const Eigen::Isometry3d& T_base_ee, double pixel_sigma_px) {
  const Dataset& dataset = *problem.dataset;
  const SetupFrames frames = FramesOf(dataset.setup);
  const Eigen::Isometry3d& T_holder_target = solved.T_holder_target[0];
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  constexpr double kStep = 1e-6;  // rad and m: far below any σ, far above rounding at 1000 px
  for (const View& view : problem.views) {
    if (view.pose != pose || !view.used || !solved.T_cam_mount[view.camera]) continue;
    const Camera& camera = dataset.cameras[view.camera];
    // The view's points in the camera for a perturbed flange.
    auto chain = [&](const Eigen::Matrix<double, 6, 1>& delta) {
      return Eigen::Isometry3d(*solved.T_cam_mount[view.camera] * frames.MountFromHolder(Perturbed(T_base_ee, delta)) *
                               T_holder_target);
    };
    std::array<Eigen::Isometry3d, 12> moved;
    for (int d = 0; d < 6; ++d) {
      Eigen::Matrix<double, 6, 1> delta = Eigen::Matrix<double, 6, 1>::Zero();
      delta[d] = kStep;
      moved[2 * d] = chain(delta);
      moved[2 * d + 1] = chain(-delta);
    }
    for (const Eigen::Vector3d& p : view.p_target) {
      Eigen::Matrix<double, 2, 6> J;
      bool projected = true;
      for (int d = 0; d < 6 && projected; ++d) {
        const auto plus = camera.Project(moved[2 * d] * p);
        const auto minus = camera.Project(moved[2 * d + 1] * p);
        projected = plus && minus;
        if (projected) J.col(d) = (*plus - *minus) / (2.0 * kStep);
      }
      if (projected) H += J.transpose() * J;
    }
  }
  return H / (pixel_sigma_px * pixel_sigma_px);
}

}  // namespace

RobotPrior UpdateRobotPrior(const Problem& problem, const Refinement& solved, const RobotPrior& prior) {
  const Dataset& dataset = *problem.dataset;
  const SetupFrames frames = FramesOf(dataset.setup);
  Eigen::Matrix<double, 6, 1> prior_information;
  prior_information << Eigen::Vector3d::Constant(1.0 / (prior.sigma_rad * prior.sigma_rad)),
      Eigen::Vector3d::Constant(1.0 / (prior.sigma_m * prior.sigma_m));
  double rotation_sum = 0, translation_sum = 0;
  int poses = 0;
  for (size_t j = 0; j < solved.T_mount_holder.size() && j < dataset.poses.size(); ++j) {
    if (!solved.T_mount_holder[j]) continue;
    // MountFromHolder is the identity or the inverse: its own inverse too.
    const Eigen::Isometry3d T_base_ee = frames.MountFromHolder(*solved.T_mount_holder[j]);
    const Eigen::Isometry3d& reported = dataset.poses[j].T_base_ee;
    // The solve's correction of the record (its posterior mean) ...
    const Eigen::Vector3d omega = RotationVectorFromMatrix(T_base_ee.linear() * reported.linear().transpose());
    const Eigen::Vector3d shift = T_base_ee.translation() - reported.translation();
    // ... and how uncertain it is: the views' information plus the prior's.
    Eigen::Matrix<double, 6, 6> information =
        FlangeInformation(problem, solved, static_cast<int>(j), T_base_ee, prior.pixel_sigma_px);
    information.diagonal() += prior_information;
    const Eigen::Matrix<double, 6, 6> posterior = information.inverse();
    // E[|δ|²] under the posterior: the mean's square plus the variance.
    rotation_sum += omega.squaredNorm() + posterior.topLeftCorner<3, 3>().trace();
    translation_sum += shift.squaredNorm() + posterior.bottomRightCorner<3, 3>().trace();
    ++poses;
  }
  RobotPrior next = prior;
  if (poses == 0) return next;
  next.sigma_rad = std::max(std::sqrt(rotation_sum / (3.0 * poses)), 1e-5 * M_PI / 180.0);
  next.sigma_m = std::max(std::sqrt(translation_sum / (3.0 * poses)), 1e-8);
  return next;
}

}  // namespace handeye::internal
