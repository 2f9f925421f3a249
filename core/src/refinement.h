// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The nonlinear refinement (refine*.cc): the joint solve and the per-camera one.

#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "initialisation.h"
#include "problem.h"
#include "robot_error.h"

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
  /// The part of that shift the camera's own held fx, fy, cx, cy make, a
  /// column each (ConsiderCovariance::ShiftOf; where it has held intrinsics).
  std::vector<std::optional<Eigen::Matrix<double, 6, 4>>> T_cam_mount_own_intrinsics_shift;
  /// With the covariance: per camera with held given intrinsics, what the
  /// views and their prior say its fx, fy, cx, cy are off by (estimate less
  /// given, pixels; 0 for those not held): the δc of that shift.
  std::vector<std::optional<Eigen::Vector4d>> intrinsics_offset_px;
  /// With the covariance: per camera, the part of T_cam_mount_covariance the
  /// held given intrinsics' uncertainty adds (ConsiderCovariance::Consider).
  std::vector<std::optional<Eigen::Matrix<double, 6, 6>>> T_cam_mount_intrinsics_covariance;
  std::optional<Eigen::Matrix<double, 6, 6>> T_holder_target_covariance;
  /// Its part the held given intrinsics' uncertainty adds.
  std::optional<Eigen::Matrix<double, 6, 6>> T_holder_target_intrinsics_covariance;
  /// With the covariance: per camera, T_cam_mount against T_holder_target
  /// (tangents), without what the given and the camera's refined intrinsics add.
  std::vector<std::optional<Eigen::Matrix<double, 6, 6>>> T_cam_mount_target_covariance;
};

/// Starts the next joint solve from `solved`: its camera transforms (where it
/// has them), its T_holder_target and, with robot pose blocks, their poses.
void WarmStart(const Refinement& solved, Initialisation* init);

/// What RefineJoint does with the problem it builds: solve it, or only
/// compute the covariance of the given values (the solution); with
/// kCovarianceRobotHeld, of a solution that took the robot poses as exact,
/// their error at `robot`'s σ an uncertain input (ConsiderCovariance::HoldIndependent).
enum class JointStep { kSolve, kCovariance, kCovarianceRobotHeld };

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

}  // namespace handeye::internal
