// SPDX-License-Identifier: GPL-2.0-or-later
// The joint solve's covariance at its solution (refine_internal.h): the
// cameras', the target transform's and the intrinsics', with the robot's
// settled error as a sandwich and the held intrinsics as considered inputs.
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <utility>

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

Eigen::Matrix<double, 6, 6> PriorJacobian(const ceres::Problem& problem,
                                          const RobotPoseBlock& block) {
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> J;
  double* jacobians[] = {J.data()};
  double cost;
  Eigen::Matrix<double, 6, 1> residuals;
  problem.EvaluateResidualBlock(block.prior, false, &cost, residuals.data(), jacobians);
  return J;
}

namespace {

/// Where the robot's error the covariance assumes (RobotPrior::CovarianceSigmaM)
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
  const double rotation = robot.CovarianceSigmaRad() / robot.sigma_rad,
               translation = robot.CovarianceSigmaM() / robot.sigma_m;
  keep << Eigen::Vector3d::Constant(1.0 - rotation * rotation),
      Eigen::Vector3d::Constant(1.0 - translation * translation);
  std::vector<Eigen::Matrix<double, 6, 6>> M;
  for (const RobotPoseBlock& block : robot_poses) {
    const Eigen::Matrix<double, 6, 6> J = PriorJacobian(problem, block);
    M.push_back(J.transpose() * keep.asDiagonal() * J);
  }
  return M;
}

/// Σ_j [A⁻¹]_xj M_j [A⁻¹]_jy, with `C(a, b)` reading [A⁻¹]_ab in tangent space.
template <typename CovarianceBlock>
Eigen::MatrixXd SandwichCorrection(const std::vector<RobotPoseBlock>& robot_poses,
                                   const std::vector<Eigen::Matrix<double, 6, 6>>& M,
                                   const CovarianceBlock& C, const double* x, const double* y) {
  Eigen::MatrixXd sum;
  for (size_t j = 0; j < robot_poses.size(); ++j) {
    const Eigen::MatrixXd term =
        C(x, robot_poses[j].pose) * M[j] * C(y, robot_poses[j].pose).transpose();
    sum = sum.size() ? Eigen::MatrixXd(sum + term) : term;
  }
  return sum;
}

/// The part of block x's covariance its refined intrinsics' uncertainty
/// adds: C_xK C_KK⁻¹ C_Ky over K's free coordinates (`solve(a, b)`: the
/// solve's covariance block; the held ones' rows are 0), x against y (x's
/// own: y = x). What is left is the covariance were the intrinsics known; a
/// later estimate through the same intrinsics shares the rest (check leaves
/// it out, as the held ones').
template <typename SolveCovariance>
Eigen::MatrixXd FromRefinedIntrinsics(const double* x, const double* y, const double* K,
                                      const std::vector<int>& held, const SolveCovariance& solve) {
  const Eigen::MatrixXd C_KK = solve(K, K), C_xK = solve(x, K), C_yK = solve(y, K);
  std::vector<int> free;
  for (int i = 0; i < C_KK.rows(); ++i)
    if (std::find(held.begin(), held.end(), i) == held.end()) free.push_back(i);
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(C_xK.rows(), C_yK.rows());
  if (free.empty()) return zero;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(C_KK(free, free));
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all()) return zero;
  return C_xK(Eigen::all, free) * ldlt.solve(C_yK(Eigen::all, free).transpose());
}

/// Fewer robot poses than this and their scatter tells too little to widen σ by.
constexpr int kMinScatterPoses = 6;

/// The free blocks the robot poses' scores are taken in: all but the robot
/// pose blocks (a pose's share of the gradient in its own block is the whole
/// gradient there, 0 at the solution).
std::vector<double*> ScatterBlocks(const ceres::Problem& problem,
                                   const std::vector<RobotPoseBlock>& robot_poses) {
  std::set<const double*> poses;
  for (const RobotPoseBlock& pose : robot_poses) poses.insert(pose.pose);
  std::vector<double*> all, out;
  problem.GetParameterBlocks(&all);
  for (double* block : all)
    if (!problem.IsParameterBlockConstant(block) && !poses.count(block)) out.push_back(block);
  return out;
}

/// Each robot pose's share of the cost's gradient (its residual blocks') in
/// the tangent spaces of `blocks` stacked, one column per pose, less their
/// mean (the priors' share); empty where fewer than kMinScatterPoses poses
/// have residuals or an evaluation fails.
Eigen::MatrixXd PoseScores(ceres::Problem* problem,
                           const std::vector<std::vector<ceres::ResidualBlockId>>& at_pose,
                           const std::vector<double*>& blocks) {
  Eigen::Index size = 0;
  for (const double* block : blocks) size += problem->ParameterBlockTangentSize(block);
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = blocks;
  std::vector<Eigen::VectorXd> columns;
  for (const std::vector<ceres::ResidualBlockId>& residuals : at_pose) {
    if (residuals.empty()) continue;
    evaluate.residual_blocks = residuals;
    double cost = 0;
    std::vector<double> gradient;
    if (!problem->Evaluate(evaluate, &cost, nullptr, &gradient, nullptr)) return {};
    columns.push_back(Eigen::Map<const Eigen::VectorXd>(gradient.data(), size));
  }
  if (static_cast<int>(columns.size()) < kMinScatterPoses) return {};
  Eigen::MatrixXd scores(size, static_cast<Eigen::Index>(columns.size()));
  for (size_t c = 0; c < columns.size(); ++c) scores.col(static_cast<Eigen::Index>(c)) = columns[c];
  scores.colwise() -= scores.rowwise().mean();
  return scores;
}

/// The cluster-robust ("sandwich") covariance of block x, A⁻¹ B A⁻¹ with
/// B = Σ_j s_j s_jᵀ · J / (J − 1) over the J robot poses' centred scores s_j:
/// how far the estimate moves when the poses are drawn again, as the poses'
/// own scatter shows it whatever the noise is (shared by a pose's points,
/// corners biased view by view, intrinsics that trade against distance).
/// Left out with a quarter of the poses, rendered cells moved 1.1-3.3 times
/// the model's σ/√3 with the intrinsics refined (0.8-2.3 with them given).
template <typename CovarianceBlock>
Eigen::MatrixXd Scatter(const double* x, const std::vector<double*>& blocks,
                        const Eigen::MatrixXd& scores, const CovarianceBlock& C) {
  Eigen::MatrixXd moves;
  Eigen::Index at = 0;
  for (const double* block : blocks) {
    const Eigen::MatrixXd C_xb = C(x, block);
    const Eigen::MatrixXd term = C_xb * scores.middleRows(at, C_xb.cols());
    moves = moves.size() ? Eigen::MatrixXd(moves + term) : term;
    at += C_xb.cols();
  }
  const double poses = static_cast<double>(scores.cols());
  return moves * moves.transpose() * (poses / (poses - 1.0));
}

/// D of a pose's covariance C (rotation, then translation) widened to D C D,
/// each part apart, to the scatter's trace where that is larger: the model
/// gives the shape (the scatter of a few poses is a rough one), the scatter a
/// floor for the size.
Eigen::Matrix<double, 6, 1> WideningOf(const Eigen::Matrix<double, 6, 6>& C,
                                       const Eigen::MatrixXd& scatter) {
  Eigen::Matrix<double, 6, 1> d;
  for (int part = 0; part < 2; ++part) {
    const double model = C.block<3, 3>(3 * part, 3 * part).trace(),
                 data = scatter.block(3 * part, 3 * part, 3, 3).trace();
    d.segment<3>(3 * part).setConstant(model > 0 && data > model ? std::sqrt(data / model) : 1.0);
  }
  return d;
}

/// The covariance blocks SolutionCovariance reads: each free camera's, the
/// target transform's and each intrinsics block's own, and each of those
/// against the robot pose blocks (`robot_poses`: the sandwich's; empty
/// without it) and against the `scattered` blocks (the scatter's).
std::vector<std::pair<const double*, const double*>> CovariancePairs(
    const ceres::Problem& problem, const std::vector<double*>& T_cam_mount, double* T_holder_target,
    const std::vector<double*>& K, const std::vector<RobotPoseBlock>& robot_poses,
    const std::vector<double*>& scattered) {
  std::vector<double*> wanted;  // the blocks whose covariance the result reports
  for (double* block : T_cam_mount)
    if (block && !problem.IsParameterBlockConstant(block)) wanted.push_back(block);
  wanted.push_back(T_holder_target);
  for (double* block : K)
    if (block) wanted.push_back(block);
  std::vector<std::pair<const double*, const double*>> pairs;
  for (double* block : wanted) {
    pairs.emplace_back(block, block);
    if (block != T_holder_target) pairs.emplace_back(block, T_holder_target);
    for (const RobotPoseBlock& pose : robot_poses) pairs.emplace_back(block, pose.pose);
    for (double* other : scattered) pairs.emplace_back(block, other);
  }
  return pairs;
}

using IntrinsicsSigmas = std::array<double, OpenCVCameraModel::kNumParams>;

/// The intrinsics block K's tangent-to-parameter Jacobian (identity without a
/// manifold; the subset manifold's rows of fixed parameters are 0).
Eigen::Matrix<double, OpenCVCameraModel::kNumParams, Eigen::Dynamic, Eigen::RowMajor>
IntrinsicsPlusJacobian(const ceres::Problem& problem, const double* K) {
  constexpr int kN = OpenCVCameraModel::kNumParams;
  Eigen::Matrix<double, kN, Eigen::Dynamic, Eigen::RowMajor> P =
      Eigen::Matrix<double, kN, Eigen::Dynamic, Eigen::RowMajor>::Identity(
          kN, problem.ParameterBlockTangentSize(K));
  if (const ceres::Manifold* manifold = problem.GetManifold(K)) manifold->PlusJacobian(K, P.data());
  return P;
}

/// 1σ of each intrinsic of block K from its tangent-space covariance `C`
/// (the free and the held uncertain intrinsics; the latter's rows are 0),
/// each no smaller than the robot poses' `scatter` of it (none: empty).
IntrinsicsSigmas IntrinsicsSigma(const ceres::Problem& problem, const double* K,
                                 const Eigen::MatrixXd& C, const Eigen::MatrixXd& scatter) {
  const auto P = IntrinsicsPlusJacobian(problem, K);
  const Eigen::MatrixXd model = P * C * P.transpose();
  const Eigen::MatrixXd floor =
      scatter.size() ? Eigen::MatrixXd(P * scatter * P.transpose()) : Eigen::MatrixXd();
  IntrinsicsSigmas sigma{};
  for (int p = 0; p < OpenCVCameraModel::kNumParams; ++p)
    sigma[p] =
        std::sqrt(std::max(0.0, floor.size() ? std::max(model(p, p), floor(p, p)) : model(p, p)));
  return sigma;
}

/// Where the covariance could not be computed: every intrinsic the solve
/// could move is undetermined (infinite σ); fixed ones stay exact.
IntrinsicsSigmas UndeterminedIntrinsicsSigma(const ceres::Problem& problem, const double* K) {
  IntrinsicsSigmas sigma;
  sigma.fill(std::numeric_limits<double>::infinity());
  if (!problem.GetManifold(K)) return sigma;
  const auto P = IntrinsicsPlusJacobian(problem, K);
  for (int p = 0; p < OpenCVCameraModel::kNumParams; ++p)
    if (P.row(p).isZero()) sigma[p] = 0.0;
  return sigma;
}

/// Every covariance field of `out` empty, for `cameras` cameras and
/// `intrinsics` intrinsics blocks (their σ 0).
void ClearCovariance(size_t cameras, size_t intrinsics, Refinement* out) {
  out->intrinsics_sigma.assign(intrinsics, {});
  for (auto& s : out->intrinsics_sigma) s.fill(0.0);
  out->T_cam_mount_covariance.assign(cameras, std::nullopt);
  out->T_cam_mount_intrinsics_shift.assign(cameras, std::nullopt);
  out->T_cam_mount_own_intrinsics_shift.assign(cameras, std::nullopt);
  out->intrinsics_offset_px.assign(cameras, std::nullopt);
  out->T_cam_mount_intrinsics_covariance.assign(cameras, std::nullopt);
  out->T_cam_mount_target_covariance.assign(cameras, std::nullopt);
  out->T_holder_target_covariance.reset();
  out->T_holder_target_intrinsics_covariance.reset();
}

}  // namespace

/// The covariance of the solution: tangent-space 6×6 of the pose blocks
/// T_cam_mount and T_holder_target, and 1σ of every intrinsic parameter, from the Jacobian at the
/// solution scaled by the a posteriori variance factor (the residuals' own
/// scale) and by the view design factor (an error the points of a view share,
/// e.g. a robot pose error not modelled, counts once per view, not per point);
/// with robot pose blocks whose settled σ differs from their prior's, the
/// sandwich of SandwichWeights; with robot poses held as reported, what
/// their error adds; and no smaller than the robot poses' own
/// scatter (Scatter). Fills `out`; leaves it empty when the Jacobian is
/// rank deficient.
void SolutionCovariance(ceres::Problem* problem, const std::vector<double*>& T_cam_mount,
                        double* T_holder_target, const std::vector<double*>& K,
                        const std::vector<ceres::ResidualBlockId>& views,
                        const std::vector<std::vector<ceres::ResidualBlockId>>& at_pose,
                        const std::optional<RobotPrior>& robot,
                        const std::vector<RobotPoseBlock>& robot_poses,
                        ConsiderCovariance* covariance, int threads, Refinement* out) {
  ClearCovariance(T_cam_mount.size(), K.size(), out);
  const bool sandwich = robot && !robot_poses.empty() && robot->CovarianceApart();
  const std::vector<double*> scattered = ScatterBlocks(*problem, robot_poses);
  const double variance_factor = VarianceFactor(problem, views);
  const bool ok = covariance->Compute(
      CovariancePairs(*problem, T_cam_mount, T_holder_target, K,
                      sandwich ? robot_poses : std::vector<RobotPoseBlock>{}, scattered),
      problem, threads);
  const Eigen::MatrixXd scores = ok ? PoseScores(problem, at_pose, scattered) : Eigen::MatrixXd();

  const std::vector<Eigen::Matrix<double, 6, 6>> M =
      sandwich ? SandwichWeights(*problem, robot_poses, *robot)
               : std::vector<Eigen::Matrix<double, 6, 6>>{};
  auto tangent_block = [&](const double* a, const double* b) { return covariance->Block(a, b); };
  // The solve's own covariance (for residuals of the variance seen), and
  // what the robot poses' error adds where they are held as reported
  // (ConsiderCovariance::Independent, in the parameters' units).
  auto solve_covariance = [&](const double* a, const double* b) {
    Eigen::MatrixXd C = tangent_block(a, b);
    if (sandwich) C -= SandwichCorrection(robot_poses, M, tangent_block, a, b);
    return Eigen::MatrixXd(C * variance_factor + covariance->Independent(a, b));
  };
  // Widened to the poses' scatter: the scale on each side of D C D.
  auto widening = [&](const double* block, const Eigen::Matrix<double, 6, 6>& C) {
    return scores.size() ? WideningOf(C, Scatter(block, scattered, scores, tangent_block))
                         : Eigen::Matrix<double, 6, 1>::Ones().eval();
  };
  if (ok) {
    const Eigen::Matrix<double, 6, 6> C_T = solve_covariance(T_holder_target, T_holder_target);
    const Eigen::DiagonalMatrix<double, 6> D_T(widening(T_holder_target, C_T));
    // Each camera's covariance less what its refined intrinsics add, which
    // joins what the held ones' error adds (already in the units of the
    // parameters: no variance factor); and against the target, without either.
    for (size_t k = 0; k < T_cam_mount.size(); ++k)
      if (T_cam_mount[k] && !problem->IsParameterBlockConstant(T_cam_mount[k])) {
        const Eigen::Matrix<double, 6, 6> C = solve_covariance(T_cam_mount[k], T_cam_mount[k]);
        const Eigen::DiagonalMatrix<double, 6> D(widening(T_cam_mount[k], C));
        auto from_refined = [&](const double* other) {
          return K[k] ? Eigen::Matrix<double, 6, 6>(FromRefinedIntrinsics(
                            T_cam_mount[k], other, K[k], covariance->Held(K[k]), solve_covariance))
                      : Eigen::Matrix<double, 6, 6>::Zero();
        };
        const Eigen::Matrix<double, 6, 6> refined = from_refined(T_cam_mount[k]);
        out->T_cam_mount_covariance[k] = D * (C - refined) * D;
        out->T_cam_mount_target_covariance[k] =
            D *
            (solve_covariance(T_cam_mount[k], T_holder_target) - from_refined(T_holder_target)) *
            D_T;
        out->T_cam_mount_intrinsics_shift[k] = covariance->Shift(T_cam_mount[k], variance_factor);
        if (K[k] && !covariance->Held(K[k]).empty()) {
          out->intrinsics_offset_px[k] = covariance->Suggested(K[k], variance_factor).head<4>();
          out->T_cam_mount_own_intrinsics_shift[k] =
              covariance->ShiftOf(T_cam_mount[k], K[k], variance_factor).leftCols<4>();
        }
        out->T_cam_mount_intrinsics_covariance[k] =
            Eigen::Matrix<double, 6, 6>(covariance->Consider(T_cam_mount[k], variance_factor)) +
            D * refined * D;
      }
    out->T_holder_target_intrinsics_covariance =
        covariance->Consider(T_holder_target, variance_factor);
    out->T_holder_target_covariance = D_T * C_T * D_T + *out->T_holder_target_intrinsics_covariance;
  }
  for (size_t k = 0; k < K.size(); ++k) {
    if (!K[k]) continue;
    if (!ok) {
      out->intrinsics_sigma[k] = UndeterminedIntrinsicsSigma(*problem, K[k]);
      continue;
    }
    const Eigen::MatrixXd scatter =
        scores.size() ? Scatter(K[k], scattered, scores, tangent_block) : Eigen::MatrixXd();
    out->intrinsics_sigma[k] =
        IntrinsicsSigma(*problem, K[k], solve_covariance(K[k], K[k]), scatter);
  }
}

}  // namespace handeye::internal
