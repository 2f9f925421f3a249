// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// What the joint solve (refine_joint.cc), the per-camera solve (refine.cc)
// and the joint solve's covariance (refine_covariance.cc) share.

#include <ceres/problem.h>
#include <ceres/solver.h>

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "consider_covariance.h"
#include "cost_functions.h"
#include "problem.h"
#include "refinement.h"
#include "robot_error.h"

namespace handeye::internal {

/// A view's target points and their detections, shared by its cost functions.
std::shared_ptr<const ViewPoints> Points(const View& view);

/// The solver's options for a chain problem of this size.
ceres::Solver::Options SolverOptions(const CalibrationOptions& options,
                                     const ceres::Problem& problem);

/// Solves; a solve that stops at the iteration limit is returned (converged
/// false) for the caller to warn about, a failed one throws.
SolverSummary Solve(ceres::Solver::Options solver, const CalibrationOptions& options,
                    ceres::Problem* problem);

/// The stacked covariance of the uncertain inputs, block-diagonal over cameras.
Eigen::MatrixXd BlockDiagonal(const std::vector<Eigen::MatrixXd>& blocks);

/// A robot pose block and the residual block of its prior.
struct RobotPoseBlock {
  double* pose;
  ceres::ResidualBlockId prior;
};

/// The Jacobian of the block's prior residuals (rotation, then translation,
/// each over its σ) in the pose block's tangent space, at its current value.
Eigen::Matrix<double, 6, 6> PriorJacobian(const ceres::Problem& problem,
                                          const RobotPoseBlock& block);

/// The joint solve's covariance at its solution (see refine_covariance.cc):
/// fills `out`'s covariances and intrinsics σ; leaves them empty when the
/// Jacobian is rank deficient. `at_pose`: the residual blocks of each robot
/// pose (its views, their cross terms, its prior), whose scatter σ is
/// widened to where the model's is smaller.
void SolutionCovariance(ceres::Problem* problem, const std::vector<double*>& T_cam_mount,
                        double* T_holder_target, const std::vector<double*>& K,
                        const std::vector<ceres::ResidualBlockId>& views,
                        const std::vector<std::vector<ceres::ResidualBlockId>>& at_pose,
                        const std::optional<RobotPrior>& robot,
                        const std::vector<RobotPoseBlock>& robot_poses,
                        ConsiderCovariance* covariance, int threads, Refinement* out);

}  // namespace handeye::internal
