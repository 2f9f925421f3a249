// SPDX-License-Identifier: GPL-2.0-or-later
// The joint solve's covariance at its solution (refine_internal.h): the
// cameras', the target transform's and the intrinsics', with the robot's
// settled error as a sandwich and the held intrinsics as considered inputs.
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <algorithm>
#include <cmath>

#include "covariance.h"
#include "refine_internal.h"
#include "refinement.h"
#include "robot_error.h"

namespace handeye::internal {

/// The stacked covariance of the uncertain inputs, block-diagonal over cameras.
Eigen::MatrixXd BlockDiagonal(const std::vector<Eigen::MatrixXd>& blocks) {
  Eigen::Index n = 0;
  for (const auto& b : blocks) n += b.rows();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, n);
  Eigen::Index at = 0;
  for (const auto& b : blocks) {
    out.block(at, at, b.rows(), b.cols()) = b;
    at += b.rows();
  }
  return out;
}

namespace {

/// Where the robot's error the covariance assumes (RobotPrior::settled_sigma_m)
/// differs from the σ of the prior the solve weighed the records with, the
/// covariance of the estimate is the sandwich A⁻¹ B A⁻¹: A = JᵀJ as solved,
/// B = JᵀΣJ with the prior residuals' variance scaled by D = (settled / prior σ)²,
/// i.e. B = A − Σ_j J_jᵀ(I − D)J_j over the prior blocks j, and
/// Cov_xy = [A⁻¹]_xy − Σ_j [A⁻¹]_xj M_j [A⁻¹]_jy with M_j = J_jᵀ(I − D)J_j.
/// These are the M_j, J_j the prior's Jacobian in the pose block's tangent space.
std::vector<Eigen::Matrix<double, 6, 6>> SandwichWeights(
    const ceres::Problem& problem, const std::vector<RobotPoseBlock>& robot_poses,
    const RobotPrior& robot) {
  Eigen::Matrix<double, 6, 1> keep;  // 1 − D per prior residual (rotation, then translation)
  const double rotation = robot.settled_sigma_rad / robot.sigma_rad,
               translation = robot.settled_sigma_m / robot.sigma_m;
  keep << Eigen::Vector3d::Constant(1.0 - rotation * rotation),
      Eigen::Vector3d::Constant(1.0 - translation * translation);
  std::vector<Eigen::Matrix<double, 6, 6>> M;
  for (const RobotPoseBlock& block : robot_poses) {
    Eigen::Matrix<double, 6, 6, Eigen::RowMajor> J;
    double* jacobians[] = {J.data()};
    double cost;
    Eigen::Matrix<double, 6, 1> residuals;
    problem.EvaluateResidualBlock(block.prior, false, &cost, residuals.data(), jacobians);
    M.push_back(J.transpose() * keep.asDiagonal() * J);
  }
  return M;
}

/// Σ_j [A⁻¹]_xj M_j [A⁻¹]_jx, with `C(a, b)` reading [A⁻¹]_ab in tangent space.
template <typename CovarianceBlock>
Eigen::MatrixXd SandwichCorrection(const std::vector<RobotPoseBlock>& robot_poses,
                                   const std::vector<Eigen::Matrix<double, 6, 6>>& M,
                                   const CovarianceBlock& C, const double* x) {
  Eigen::MatrixXd sum;
  for (size_t j = 0; j < robot_poses.size(); ++j) {
    const Eigen::MatrixXd C_xj = C(x, robot_poses[j].pose);
    const Eigen::MatrixXd term = C_xj * M[j] * C_xj.transpose();
    sum = sum.size() ? Eigen::MatrixXd(sum + term) : term;
  }
  return sum;
}

}  // namespace

/// The covariance of the solution: tangent-space 6×6 of the pose blocks
/// T_cam_mount and T_holder_target, and 1σ of every intrinsic parameter, from the Jacobian at the
/// solution scaled by the a posteriori variance factor (the residuals' own
/// scale) and by the view design factor (an error the points of a view share,
/// e.g. a robot pose error not modelled, counts once per view, not per point);
/// with robot pose blocks whose settled σ differs from their prior's, the
/// sandwich of SandwichWeights. Fills `out`; leaves it empty when the
/// Jacobian is rank deficient.
void SolutionCovariance(ceres::Problem* problem, const std::vector<double*>& T_cam_mount,
                        double* T_holder_target, const std::vector<double*>& K,
                        const std::vector<ceres::ResidualBlockId>& views,
                        const std::optional<RobotPrior>& robot,
                        const std::vector<RobotPoseBlock>& robot_poses,
                        ConsiderCovariance* covariance, int threads, Refinement* out) {
  constexpr int kN = OpenCVCameraModel::kNumParams;
  out->intrinsics_sigma.assign(K.size(), {});
  for (auto& s : out->intrinsics_sigma) s.fill(0.0);
  out->T_cam_mount_covariance.assign(T_cam_mount.size(), std::nullopt);
  out->T_holder_target_covariance.reset();
  const bool sandwich =
      robot && !robot_poses.empty() && robot->settled_sigma_m > 0 && robot->settled_sigma_rad > 0 &&
      (robot->settled_sigma_m != robot->sigma_m || robot->settled_sigma_rad != robot->sigma_rad);
  std::vector<double*> wanted;  // the blocks whose covariance the result reports
  for (double* block : T_cam_mount)
    if (block && !problem->IsParameterBlockConstant(block)) wanted.push_back(block);
  wanted.push_back(T_holder_target);
  for (double* block : K)
    if (block) wanted.push_back(block);
  std::vector<std::pair<const double*, const double*>> pairs;
  for (double* block : wanted) {
    pairs.emplace_back(block, block);
    if (sandwich)
      for (const RobotPoseBlock& pose : robot_poses) pairs.emplace_back(block, pose.pose);
  }
  const double variance_factor = VarianceFactor(problem, views);
  const bool ok = covariance->Compute(pairs, problem, threads);

  const std::vector<Eigen::Matrix<double, 6, 6>> M =
      sandwich ? SandwichWeights(*problem, robot_poses, *robot)
               : std::vector<Eigen::Matrix<double, 6, 6>>{};
  auto tangent_block = [&](const double* a, const double* b) { return covariance->Block(a, b); };
  // The solve's own covariance, then what the held intrinsics' error adds
  // (already in the units of the parameters: no variance factor).
  auto pose_covariance = [&](const double* block) {
    Eigen::MatrixXd C = tangent_block(block, block);
    if (sandwich) C -= SandwichCorrection(robot_poses, M, tangent_block, block);
    return Eigen::Matrix<double, 6, 6>(C * variance_factor);
  };
  out->T_cam_mount_intrinsics_shift.assign(T_cam_mount.size(), std::nullopt);
  out->T_cam_mount_intrinsics_covariance.assign(T_cam_mount.size(), std::nullopt);
  if (ok) {
    for (size_t k = 0; k < T_cam_mount.size(); ++k)
      if (T_cam_mount[k] && !problem->IsParameterBlockConstant(T_cam_mount[k])) {
        out->T_cam_mount_covariance[k] = pose_covariance(T_cam_mount[k]);
        out->T_cam_mount_intrinsics_shift[k] = covariance->Shift(T_cam_mount[k], variance_factor);
        out->T_cam_mount_intrinsics_covariance[k] =
            covariance->Consider(T_cam_mount[k], variance_factor);
      }
    out->T_holder_target_covariance =
        pose_covariance(T_holder_target) + covariance->Consider(T_holder_target, variance_factor);
  }
  for (size_t k = 0; k < K.size(); ++k) {
    if (!K[k]) continue;
    Eigen::Matrix<double, kN, kN, Eigen::RowMajor> C =
        Eigen::Matrix<double, kN, kN, Eigen::RowMajor>::Zero();
    const ceres::Manifold* manifold = problem->GetManifold(K[k]);
    if (ok) {
      // In the tangent space (the free and the held uncertain intrinsics;
      // the latter's rows are 0), back to all 18.
      Eigen::Matrix<double, kN, Eigen::Dynamic, Eigen::RowMajor> P =
          Eigen::Matrix<double, kN, Eigen::Dynamic, Eigen::RowMajor>::Identity(
              kN, problem->ParameterBlockTangentSize(K[k]));
      if (manifold) manifold->PlusJacobian(K[k], P.data());
      Eigen::MatrixXd C_tangent = tangent_block(K[k], K[k]);
      if (sandwich) C_tangent -= SandwichCorrection(robot_poses, M, tangent_block, K[k]);
      C = P * C_tangent * P.transpose();
    }
    for (int p = 0; p < kN; ++p)
      out->intrinsics_sigma[k][p] = ok ? std::sqrt(std::max(0.0, C(p, p)) * variance_factor)
                                       : std::numeric_limits<double>::infinity();
    if (!ok && manifold) {
      // Fixed parameters stay exact: the subset manifold's plus is the identity on them.
      Eigen::Matrix<double, kN, Eigen::Dynamic, Eigen::RowMajor> P(kN, manifold->TangentSize());
      manifold->PlusJacobian(K[k], P.data());
      for (int p = 0; p < kN; ++p)
        if (P.row(p).isZero()) out->intrinsics_sigma[k][p] = 0.0;
    }
  }
}

}  // namespace handeye::internal
