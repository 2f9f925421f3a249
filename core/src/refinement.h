// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The nonlinear refinement (refine*.cc), its robust rounds, the robot's
// error estimated and settled, and the leave-one-pose-out check.

#include <functional>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "closed_form.h"
#include "problem.h"

namespace handeye::internal {

/// Output of a nonlinear refinement.
struct Refinement {
  std::vector<std::optional<Eigen::Isometry3d>> T_cam_mount;
  std::vector<Eigen::Isometry3d> T_holder_target;  ///< one (joint) or one per camera (per-camera)
  std::map<std::pair<int, int>, Eigen::Isometry3d> pairs;  ///< (k, t) → T_camk_camt
  SolverSummary summary;
  /// With a robot prior: per pose, the solved robot pose (nullopt for poses without views).
  std::vector<std::optional<Eigen::Isometry3d>> T_mount_holder;
  /// Per camera (joint solve): the intrinsics after the solve.
  std::vector<std::array<double, OpenCVCameraModel::kNumParams>> intrinsics;
  /// JointStep::kCovariance: 1σ of the free intrinsics (scaled by the
  /// residuals seen; 0 for fixed ones, infinite when the views cannot
  /// determine them at all), and the tangent-space covariance of each
  /// T_cam_mount and of T_holder_target (Ceres' quaternion-manifold tangent then translation; empty
  /// when the Jacobian is rank deficient).
  std::vector<std::array<double, OpenCVCameraModel::kNumParams>> intrinsics_sigma;
  std::vector<std::optional<Eigen::Matrix<double, 6, 6>>> T_cam_mount_covariance;
  /// With the covariance: per camera, where its T_cam_mount would be (tangent)
  /// with the held given intrinsics at what their prior and the views together
  /// say (ConsiderCovariance::Shift; zero when they are exact or all refined).
  std::vector<std::optional<Eigen::Matrix<double, 6, 1>>> T_cam_mount_intrinsics_shift;
  /// With the covariance: per camera, the part of T_cam_mount_covariance the
  /// held given intrinsics' uncertainty adds (ConsiderCovariance::Consider).
  std::vector<std::optional<Eigen::Matrix<double, 6, 6>>> T_cam_mount_intrinsics_covariance;
  std::optional<Eigen::Matrix<double, 6, 6>> T_holder_target_covariance;
};

/// Starts the next joint solve from `solved`: its camera transforms (where it
/// has them), its T_holder_target and, with robot pose blocks, their poses.
void WarmStart(const Refinement& solved, Initialisation* init);

/// What RefineJoint does with the problem it builds: solve it, or only
/// compute the covariance of the given values (the solution).
enum class JointStep { kSolve, kCovariance };

/// Expectation maximisation of the robot's σ over the solution's pose blocks
/// (`solution`, solved from `init` under `robot`): each step takes every
/// record's correction plus its posterior variance (the views' information
/// about the flange and the prior's) and solves a copy again, until σ moves
/// < 5 % (≤ 4 steps). Sets robot->settled_sigma_m and settled_sigma_rad. The
/// estimate rule (EstimateRobotPrior) errs wide on purpose; this is what the
/// pose blocks say.
void SettleRobotSigma(const Problem& problem, const Initialisation& init,
                      const Refinement& solution, const CalibrationOptions& options,
                      RobotPrior* robot);

/// The robot's pose error as the views show it through the chain: nullopt when
/// the residuals through the chain are not clearly above PnP's (over 1.2×;
/// the robot is then as exact as the images can tell); else σ of the flange's
/// displacement across the viewing rays and of its rotation, from the medians
/// of where PnP and the chain put the target, less PnP's own noise there.
std::optional<RobotPrior> EstimateRobotPrior(
    const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target);

/// The paper's joint solve: shared T_holder_target, optional c_cross terms; with `robot`,
/// every robot pose is a block of the solve too, under its prior.
Refinement RefineJoint(const Problem& problem, const Initialisation& init,
                       const CalibrationOptions& options,
                       const std::optional<RobotPrior>& robot = std::nullopt,
                       JointStep step = JointStep::kSolve);
/// One T_holder_target per camera, no cross terms (for --method per-camera).
/// JointStep::kCovariance: no solve, each camera's T_cam_mount_covariance at
/// the given values, its given intrinsics uncertain inputs.
Refinement RefinePerCamera(const Problem& problem,
                           const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                           const std::vector<Eigen::Isometry3d>& T_holder_target,
                           const CalibrationOptions& options, JointStep step = JointStep::kSolve);

/// Per camera, the T_holder_target its views use (one shared, or one per camera).
TargetPoses TargetPosesOf(const Refinement& refined, size_t num_cameras);

/// The nonlinear solve made robust: `solve(scale)` runs one refinement
/// (warm-started by the caller from the last one). After each solve, views far
/// outside the robust residual distribution are excluded and the loss scale is
/// set from the residuals (when not fixed), then it solves again, until
/// nothing changes (at most a few rounds). Warnings go to *warnings.
Refinement RobustSolve(Problem* problem, const CalibrationOptions& options, double first_scale,
                       const std::function<Refinement(double scale_px)>& solve,
                       std::vector<Warning>* warnings);

/// Leave-one-pose-out: for each robot pose with used views, the joint solve
/// without them (from `init`, the solution), its prediction of their points,
/// and how far each camera moved from the full solve. One entry per camera.
void CrossValidate(const Problem& problem, const Initialisation& init,
                   const CalibrationOptions& options, const std::optional<RobotPrior>& robot,
                   std::vector<CameraResult::CrossValidation>* out);

}  // namespace handeye::internal
