// SPDX-License-Identifier: GPL-2.0-or-later
// The robot's own pose error as the solved pose blocks show it: expectation
// maximisation over the robot pose blocks, for the uncertainty of the result.
#include <algorithm>
#include <array>
#include <cmath>

#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"
#include "initialisation.h"
#include "problem.h"
#include "refinement.h"

namespace handeye::internal {
namespace {

/// At most this many expectation-maximisation steps; most settle within 5 %
/// in two or three.
constexpr int kMaxSteps = 4;

/// A perturbation of the flange pose in the prior's coordinates: a turn ω
/// about the base frame's axes through the flange (R → exp(ω)·R) and a shift
/// δt of the flange position, both in the base frame (RobotPosePrior's residuals).
Eigen::Isometry3d Perturbed(const Eigen::Isometry3d& T_base_ee,
                            const Eigen::Matrix<double, 6, 1>& delta) {
  Eigen::Isometry3d T = T_base_ee;
  T.linear() = MatrixFromRotationVector(delta.head<3>()) * T_base_ee.linear();
  T.translation() += delta.tail<3>();
  return T;
}

/// How well a pose's views alone locate its flange, given the solved camera
/// and target transforms: the information matrix Σ JᵀJ / σ² of the views'
/// points with respect to the perturbation above (central differences).
Eigen::Matrix<double, 6, 6> FlangeInformation(const Problem& problem, const Refinement& solved,
                                              int pose, const Eigen::Isometry3d& T_base_ee,
                                              double pixel_sigma_px) {
  const Dataset& dataset = *problem.dataset;
  const SetupFrames frames = FramesOf(dataset.setup);
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  constexpr double kStep = 1e-6;  // rad and m: far below any σ, far above rounding at 1000 px
  for (const View& view : problem.views) {
    if (view.pose != pose || !view.used || !solved.T_cam_mount[view.camera]) continue;
    Camera camera = dataset.cameras[view.camera];
    camera.params = solved.intrinsics[view.camera];
    std::array<Eigen::Isometry3d, 12> moved;  // the view's chain for ± each perturbation
    for (int d = 0; d < 6; ++d)
      for (int sign : {1, -1}) {
        Eigen::Matrix<double, 6, 1> delta = Eigen::Matrix<double, 6, 1>::Zero();
        delta[d] = sign * kStep;
        moved[2 * d + (sign < 0)] = *solved.T_cam_mount[view.camera] *
                                    frames.MountFromHolder(Perturbed(T_base_ee, delta)) *
                                    solved.T_holder_target[0];
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

/// One step: per axis, the mean over the robot pose blocks of the squared
/// correction of the record (its posterior mean) plus its posterior variance
/// (the views' information about the flange plus the prior's).
void UpdateSettledSigma(const Problem& problem, const Refinement& solved, RobotPrior* robot) {
  const Dataset& dataset = *problem.dataset;
  const SetupFrames frames = FramesOf(dataset.setup);
  Eigen::Matrix<double, 6, 1> prior_information;
  prior_information << Eigen::Vector3d::Constant(
      1.0 / (robot->settled_sigma_rad * robot->settled_sigma_rad)),
      Eigen::Vector3d::Constant(1.0 / (robot->settled_sigma_m * robot->settled_sigma_m));
  double rotation_sum = 0, translation_sum = 0;
  int poses = 0;
  for (size_t j = 0; j < solved.T_mount_holder.size() && j < dataset.poses.size(); ++j) {
    if (!solved.T_mount_holder[j]) continue;
    // MountFromHolder is the identity or the inverse: its own inverse too.
    const Eigen::Isometry3d T_base_ee = frames.MountFromHolder(*solved.T_mount_holder[j]);
    const Eigen::Isometry3d& reported = dataset.poses[j].T_base_ee;
    const Eigen::Vector3d omega =
        RotationVectorFromMatrix(T_base_ee.linear() * reported.linear().transpose());
    const Eigen::Vector3d shift = T_base_ee.translation() - reported.translation();
    Eigen::Matrix<double, 6, 6> information =
        FlangeInformation(problem, solved, static_cast<int>(j), T_base_ee, robot->pixel_sigma_px);
    information.diagonal() += prior_information;
    const Eigen::Matrix<double, 6, 6> posterior = information.inverse();
    rotation_sum += omega.squaredNorm() + posterior.topLeftCorner<3, 3>().trace();
    translation_sum += shift.squaredNorm() + posterior.bottomRightCorner<3, 3>().trace();
    ++poses;
  }
  if (poses == 0) return;
  robot->settled_sigma_rad = std::max(std::sqrt(rotation_sum / (3.0 * poses)), 1e-5 * M_PI / 180.0);
  robot->settled_sigma_m = std::max(std::sqrt(translation_sum / (3.0 * poses)), 1e-8);
}

}  // namespace

void SettleRobotSigma(const Problem& problem, const Initialisation& init,
                      const Refinement& solution, const CalibrationOptions& options,
                      RobotPrior* robot) {
  // The steps solve copies: the solution stays the one under the prior's own
  // σ (see RobotPrior::settled_sigma_m).
  Initialisation start = init;
  Refinement solved = solution;
  RobotPrior settled = *robot;
  settled.settled_sigma_m = robot->sigma_m;
  settled.settled_sigma_rad = robot->sigma_rad;
  for (int step = 0; step < kMaxSteps; ++step) {
    const double sigma_m = settled.settled_sigma_m, sigma_rad = settled.settled_sigma_rad;
    UpdateSettledSigma(problem, solved, &settled);
    const double change = std::max(std::abs(std::log(settled.settled_sigma_m / sigma_m)),
                                   std::abs(std::log(settled.settled_sigma_rad / sigma_rad)));
    if (change < 0.05) break;
    RobotPrior weights = settled;
    weights.sigma_m = settled.settled_sigma_m;
    weights.sigma_rad = settled.settled_sigma_rad;
    WarmStart(solved, &start);
    solved = RefineJoint(problem, start, options, weights);
  }
  robot->settled_sigma_m = settled.settled_sigma_m;
  robot->settled_sigma_rad = settled.settled_sigma_rad;
  // REML's count: the records' degrees of freedom (6 per pose) less those
  // the solved cameras, the target and the refined intrinsics took.
  int poses = 0, cameras = 0;
  size_t free_intrinsics = 0;
  for (const auto& T : solved.T_mount_holder) poses += T ? 1 : 0;
  for (size_t k = 0; k < solved.T_cam_mount.size(); ++k) {
    if (!solved.T_cam_mount[k]) continue;
    ++cameras;
    if (k < init.free_intrinsics.size()) free_intrinsics += init.free_intrinsics[k].size();
  }
  const double kept = RobotRecordsKept(poses, cameras, free_intrinsics);
  robot->settled_dof_scale = kept > 0 ? std::min(std::sqrt(poses / kept), 2.0) : 2.0;
}

std::string ModelByHeldOut(const std::vector<ModelCandidate>& candidates,
                           const std::vector<size_t>& preferred) {
  const auto best = std::min_element(candidates.begin(), candidates.end(),
                                     [](const ModelCandidate& a, const ModelCandidate& b) {
                                       return a.held_out_rms_px < b.held_out_rms_px;
                                     });
  if (best == candidates.end()) return "";
  if (best->points == 0) return candidates[preferred.at(0)].name;
  for (const size_t i : preferred)
    if (candidates.at(i).held_out_rms_px <= kModelsAlikeHeldOut * best->held_out_rms_px)
      return candidates[i].name;
  return best->name;
}

std::vector<size_t> PreferredModels(bool robot_error_clear, bool given_intrinsics_off,
                                    size_t num_candidates) {
  std::vector<size_t> preferred = {robot_error_clear ? size_t{1} : size_t{0}, num_candidates - 1};
  if (given_intrinsics_off && preferred.front() != 0) preferred.insert(preferred.begin(), 0);
  return preferred;
}

}  // namespace handeye::internal
