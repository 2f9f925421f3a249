// SPDX-License-Identifier: GPL-2.0-or-later
// The nonlinear refinement: the paper's joint problem (shared T_holder_target, c_rpj + c_cross
// under a Cauchy loss) and the per-camera variant.
#include <ceres/iteration_callback.h>
#include <ceres/manifold.h>
#include <ceres/ordered_groups.h>
#include <ceres/problem.h>
#include <ceres/product_manifold.h>
#include <ceres/solver.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <stdexcept>
#include <tuple>

#include "calibration_internal.h"
#include "chain_problem.h"
#include "consider_covariance.h"
#include "handeye/core/cost_functions.h"
#include "handeye/core/error.h"
#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"

namespace handeye::internal {
namespace {

/// Stops the solve when no pose block moves by more than the tolerances in an
/// iteration: a convergence test in millimetres and degrees, which the
/// relative tolerances of Ceres (on the cost and the parameter vector) are not.
class StepTolerance : public ceres::IterationCallback {
 public:
  StepTolerance(std::vector<const double*> blocks, const CalibrationOptions& options)
      : blocks_(std::move(blocks)),
        max_translation_m_(options.step_tolerance_mm / 1000.0),
        max_rotation_rad_(options.step_tolerance_deg * M_PI / 180.0) {
    for (const double* block : blocks_) previous_.push_back(FromPoseParams(block));
  }

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (summary.iteration == 0 || !summary.step_is_successful) return ceres::SOLVER_CONTINUE;
    bool moved = false;
    for (size_t i = 0; i < blocks_.size(); ++i) {
      const Eigen::Isometry3d now = FromPoseParams(blocks_[i]);
      moved = moved ||
              (now.translation() - previous_[i].translation()).norm() > max_translation_m_ ||
              RotationDistance(now.rotation(), previous_[i].rotation()) > max_rotation_rad_;
      previous_[i] = now;
    }
    return moved ? ceres::SOLVER_CONTINUE : ceres::SOLVER_TERMINATE_SUCCESSFULLY;
  }

 private:
  std::vector<const double*> blocks_;
  std::vector<Eigen::Isometry3d> previous_;
  double max_translation_m_, max_rotation_rad_;
};

std::shared_ptr<const ViewPoints> Points(const View& view) {
  return std::make_shared<const ViewPoints>(ViewPoints{view.p_target, view.observation->points_px});
}

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

ceres::Solver::Options SolverOptions(const CalibrationOptions& options,
                                     const ceres::Problem& problem) {
  ceres::Solver::Options solver;
  // The problem has no landmarks, only pose blocks, so the normal equations
  // are small (6 per block). A dense Jacobian is cheapest while it is small;
  // past that, the block-sparse Jacobian avoids multiplying its zeros (each
  // view touches two or three blocks).
  const double dense_jacobian_entries =
      static_cast<double>(problem.NumResiduals()) * problem.NumParameters();
  solver.linear_solver_type =
      dense_jacobian_entries <= 2e6 ? ceres::DENSE_NORMAL_CHOLESKY : ceres::SPARSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = 1e-12;
  solver.gradient_tolerance = 1e-14;
  solver.parameter_tolerance = 1e-12;
  solver.num_threads = options.threads;
  solver.logging_type = ceres::SILENT;
  return solver;
}

/// Solves; a solve that stops at the iteration limit is returned (converged
/// false) for the caller to warn about, a failed one throws.
SolverSummary Solve(ceres::Solver::Options solver, const CalibrationOptions& options,
                    ceres::Problem* problem) {
  std::vector<double*> blocks, poses;
  problem->GetParameterBlocks(&blocks);
  for (double* block : blocks)
    if (problem->ParameterBlockSize(block) == 7) poses.push_back(block);
  StepTolerance step_tolerance({poses.begin(), poses.end()}, options);
  solver.callbacks.push_back(&step_tolerance);
  solver.update_state_every_iteration = true;  // the callback reads the blocks
  ceres::Solver::Summary summary;
  const auto start = std::chrono::steady_clock::now();
  ceres::Solve(solver, problem, &summary);
  SolverSummary out;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.iterations = static_cast<int>(summary.iterations.size()) - 1;
  out.converged = summary.termination_type == ceres::CONVERGENCE ||
                  summary.termination_type == ceres::USER_SUCCESS;
  out.termination = summary.termination_type == ceres::USER_SUCCESS
                        ? "CONVERGENCE (steps below the mm/deg tolerances)"
                        : ceres::TerminationTypeToString(summary.termination_type);
  out.cauchy_scale_px = options.cauchy_scale_px;
  out.rounds = 1;
  if (summary.termination_type == ceres::FAILURE || summary.termination_type == ceres::USER_FAILURE)
    throw SolveError("the nonlinear solver failed: " + summary.message);
  return out;
}

/// A robot pose block and the residual block of its prior.
struct RobotPoseBlock {
  double* pose;
  ceres::ResidualBlockId prior;
};

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

}  // namespace

Refinement RefineJoint(const Problem& problem, const Initialisation& init,
                       const CalibrationOptions& options, const std::optional<RobotPrior>& robot,
                       JointStep step) {
  const Dataset& dataset = *problem.dataset;
  // T_holder_target, the cameras, the robot poses, the pairs (k, t); the intrinsics.
  const size_t n_cameras = dataset.cameras.size();
  ChainProblem chain(1 + n_cameras + dataset.poses.size() + n_cameras * n_cameras, n_cameras);
  ceres::Problem& ceres_problem = chain.problem();

  double* T_holder_target = chain.AddPose(init.T_holder_target);
  std::vector<double*> T_cam_mount(dataset.cameras.size(), nullptr);
  for (size_t k = 0; k < T_cam_mount.size(); ++k) {
    if (!init.T_cam_mount[k] || problem.camera_views[k].empty()) continue;
    T_cam_mount[k] = chain.AddPose(*init.T_cam_mount[k],
                                   k < init.fixed_T_cam_mount.size() && init.fixed_T_cam_mount[k]);
  }

  // Free intrinsics: one block of 18 per camera, the fixed ones held by a subset manifold.
  using Intrinsics = std::array<double, OpenCVCameraModel::kNumParams>;
  std::vector<Intrinsics> K(dataset.cameras.size());
  std::vector<double*> K_block(dataset.cameras.size(), nullptr);
  // For the covariance, the given intrinsics that stay held are uncertain
  // inputs too (ConsiderCovariance): unknowns of the problem under a prior.
  std::vector<ConsiderCovariance::Coordinates> uncertain_coordinates;
  std::vector<Eigen::MatrixXd> uncertain_covariances, uncertain_prior_information;
  for (size_t k = 0; k < K.size(); ++k) {
    K[k] = dataset.cameras[k].params;
    if (!T_cam_mount[k]) continue;
    const std::vector<int> free =
        k < init.free_intrinsics.size() ? init.free_intrinsics[k] : std::vector<int>{};
    const UncertainIntrinsics uncertain =
        step == JointStep::kCovariance
            ? UncertainGivenIntrinsics(dataset.cameras[k], free, options.intrinsics_sigma)
            : UncertainIntrinsics{};
    std::vector<int> uncertain_tangent;
    const std::vector<int> unknowns = IntrinsicsUnknowns(free, uncertain, &uncertain_tangent);
    if (unknowns.empty()) continue;
    K_block[k] = chain.AddIntrinsics(K[k], unknowns);
    if (!free.empty())
      ceres_problem.AddResidualBlock(
          IntrinsicsPrior(init.given_cameras[k], free, init.pixel_sigma_px), nullptr, K_block[k]);
    if (!uncertain.params.empty()) {
      ceres_problem.AddResidualBlock(
          UncertainIntrinsicsPrior(dataset.cameras[k], uncertain, init.pixel_sigma_px), nullptr,
          K_block[k]);
      uncertain_coordinates.push_back({K_block[k], uncertain_tangent});
      uncertain_covariances.push_back(uncertain.covariance);
      uncertain_prior_information.push_back(
          UncertainIntrinsicsPriorInformation(uncertain, init.pixel_sigma_px));
    }
  }

  // With a robot prior, each robot pose with a used view is a block, tied to
  // the reported pose by its prior.
  std::vector<double*> T_mount_holder(dataset.poses.size(), nullptr);
  std::vector<RobotPoseBlock> robot_poses;
  auto robot_pose = [&](int j) {
    if (!T_mount_holder[j]) {
      ceres::ResidualBlockId prior;
      T_mount_holder[j] = chain.AddRobotPose(
          j < static_cast<int>(init.T_mount_holder.size()) && init.T_mount_holder[j]
              ? *init.T_mount_holder[j]
              : problem.T_mount_holder[j],
          dataset.poses[j], dataset.setup, *robot, &prior);
      robot_poses.push_back({T_mount_holder[j], prior});
    }
    return T_mount_holder[j];
  };
  // One view's reprojection cost through camera block `camera_block` (T_camk_mount, direct or via
  // t).
  std::vector<ceres::ResidualBlockId> direct_blocks;  // c_rpj, one per view
  auto add_view = [&](const View& view, int k, double* camera_block,
                      std::shared_ptr<const ViewPoints> view_points) {
    const bool free_intrinsics = K_block[k] != nullptr;
    std::vector<double*> blocks = {camera_block};
    ceres::CostFunction* cost;
    if (robot) {
      cost = ViewReprojectionWithRobotError::Create(dataset.cameras[k], std::move(view_points),
                                                    options.cauchy_scale_px, free_intrinsics);
      blocks.push_back(robot_pose(view.pose));
    } else {
      cost = ViewReprojectionError::Create(dataset.cameras[k], problem.T_mount_holder[view.pose],
                                           std::move(view_points), options.cauchy_scale_px,
                                           free_intrinsics);
    }
    blocks.push_back(T_holder_target);
    if (free_intrinsics) blocks.push_back(K_block[k]);
    return ceres_problem.AddResidualBlock(cost, nullptr, blocks);
  };

  // c_rpj: every point of every used view (one block per view, the loss per point).
  // A view's points are shared by its c_rpj block and its c_cross blocks.
  std::vector<std::vector<int>> views_at_pose(dataset.poses.size());
  std::vector<std::shared_ptr<const ViewPoints>> points(problem.views.size());
  for (size_t v = 0; v < problem.views.size(); ++v) {
    const View& view = problem.views[v];
    if (!view.used || !T_cam_mount[view.camera]) continue;
    views_at_pose[view.pose].push_back(static_cast<int>(v));
    points[v] = Points(view);
    direct_blocks.push_back(add_view(view, view.camera, T_cam_mount[view.camera], points[v]));
  }

  // c_cross: at each pose, for each ordered pair (k, t) of cameras that both
  // detected the target, camera k's points predicted through camera t:
  // π_k(T_camk_camt · T_camt_mount · T_mount_holder[j] · T_holder_target · p).
  // T_camk_camt is free (one block per pair), so the term is solved in the
  // variable T_camk_mount_via_t = T_camk_camt · T_camt_mount (camera k's pose
  // as seen through camera t; the paper's Y_kt) and T_camk_camt =
  // T_camk_mount_via_t · T_mount_camt is read back after the solve:
  // (T_camk_camt, T_camt_mount) -> (T_camk_mount_via_t, T_camt_mount) is a
  // bijection, so the cost, its minimum and the minimiser are the paper's,
  // while each c_cross block touches two blocks instead of three (a third
  // less Jacobian to store, evaluate and eliminate).
  std::map<std::pair<int, int>, double*> pair_blocks;  // (k, t) -> T_camk_mount_via_t
  if (options.cross_terms) {
    for (const auto& at_pose : views_at_pose)
      for (int vk : at_pose)
        for (int vt : at_pose) {
          if (vk == vt) continue;
          const View& view_k = problem.views[vk];
          const int k = view_k.camera, t = problem.views[vt].camera;
          double*& T_camk_mount_via_t = pair_blocks[{k, t}];
          if (!T_camk_mount_via_t) {
            // T_camk_camt starts at T_camk_mount · T_mount_camt, so this block at T_camk_mount.
            T_camk_mount_via_t = chain.AddPose(*init.T_cam_mount[k]);
          }
          add_view(view_k, k, T_camk_mount_via_t, points[vk]);
        }
  }

  // Every residual block touches T_holder_target and exactly one other block
  // (T_camk_mount, direct or via t), so all of those are eliminated block by
  // block (Schur complement, built on all threads) and only T_holder_target's
  // 6×6 system is left to factor. Forming
  // JᵀJ of the whole Jacobian instead (sparse normal Cholesky) ran on one
  // thread and copied the Jacobian, ~10x larger with the cross blocks than
  // the c_rpj part, at every step to append the LM diagonal.
  // With robot pose blocks, those are eliminated instead (each residual block
  // touches one), and the cameras, pairs and T_holder_target form the reduced system.
  ceres::Solver::Options solver = SolverOptions(options, ceres_problem);
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  const int camera_group = robot ? 1 : 0;
  for (double* block : T_cam_mount)
    if (block) ordering->AddElementToGroup(block, camera_group);
  for (const auto& [pair, block] : pair_blocks) ordering->AddElementToGroup(block, camera_group);
  for (double* block : T_mount_holder)
    if (block) ordering->AddElementToGroup(block, 0);
  ordering->AddElementToGroup(T_holder_target, 1);
  for (double* block : K_block)
    if (block) ordering->AddElementToGroup(block, 1);
  solver.linear_solver_type = ceres::DENSE_SCHUR;
  solver.linear_solver_ordering = ordering;
  // The closed-form start is close, so the first steps can be near
  // Gauss-Newton: with Ceres' default radius (1e4) the damping held the
  // convergence back by one or two iterations (16 and 32 cameras: 6-7 -> 5)
  // on the way to the same minimum.
  solver.initial_trust_region_radius = 1e6;
  Refinement out;
  if (step == JointStep::kSolve) out.summary = Solve(solver, options, &ceres_problem);
  out.T_holder_target.push_back(ChainProblem::Pose(T_holder_target));
  out.T_cam_mount.resize(T_cam_mount.size());
  for (size_t k = 0; k < T_cam_mount.size(); ++k)
    if (T_cam_mount[k]) out.T_cam_mount[k] = ChainProblem::Pose(T_cam_mount[k]);
  for (const auto& [pair, T_camk_mount_via_t] : pair_blocks)
    out.pairs[pair] =
        ChainProblem::Pose(T_camk_mount_via_t) * out.T_cam_mount[pair.second]->inverse();
  for (size_t k = 0; k < K.size(); ++k)
    if (K_block[k]) std::copy(K_block[k], K_block[k] + K[k].size(), K[k].begin());
  out.intrinsics = K;
  out.T_mount_holder.resize(T_mount_holder.size());
  for (size_t j = 0; j < T_mount_holder.size(); ++j)
    if (T_mount_holder[j]) out.T_mount_holder[j] = ChainProblem::Pose(T_mount_holder[j]);
  if (step == JointStep::kCovariance) {
    ConsiderCovariance covariance(uncertain_coordinates, BlockDiagonal(uncertain_covariances),
                                  BlockDiagonal(uncertain_prior_information));
    SolutionCovariance(&ceres_problem, T_cam_mount, T_holder_target, K_block, direct_blocks, robot,
                       robot_poses, &covariance, options.threads, &out);
  }
  return out;
}

void WarmStart(const Refinement& solved, Initialisation* init) {
  for (size_t k = 0; k < solved.T_cam_mount.size(); ++k)
    if (solved.T_cam_mount[k]) init->T_cam_mount[k] = solved.T_cam_mount[k];
  init->T_holder_target = solved.T_holder_target[0];
  if (!solved.T_mount_holder.empty()) init->T_mount_holder = solved.T_mount_holder;
}

Refinement RefinePerCamera(const Problem& problem,
                           const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount_start,
                           const std::vector<Eigen::Isometry3d>& T_holder_target_start,
                           const CalibrationOptions& options, JointStep step) {
  const Dataset& dataset = *problem.dataset;
  Refinement out;
  out.T_cam_mount.resize(dataset.cameras.size());
  out.T_cam_mount_covariance.resize(dataset.cameras.size());
  out.T_cam_mount_intrinsics_shift.resize(dataset.cameras.size());
  out.T_cam_mount_intrinsics_covariance.resize(dataset.cameras.size());
  out.T_holder_target = T_holder_target_start;
  out.summary.converged = true;  // until a camera's solve does not
  out.summary.cauchy_scale_px = options.cauchy_scale_px;
  out.summary.rounds = 1;
  for (size_t k = 0; k < dataset.cameras.size(); ++k) {
    if (!T_cam_mount_start[k] || problem.camera_views[k].empty()) continue;
    ChainProblem chain(2, 1);
    ceres::Problem& ceres_problem = chain.problem();
    double* T_cam_mount = chain.AddPose(*T_cam_mount_start[k]);
    double* T_holder_target = chain.AddPose(T_holder_target_start[k]);
    // For the covariance, the camera's given intrinsics as uncertain inputs (ConsiderCovariance).
    const UncertainIntrinsics uncertain =
        step == JointStep::kCovariance
            ? UncertainGivenIntrinsics(dataset.cameras[k], {}, options.intrinsics_sigma)
            : UncertainIntrinsics{};
    std::vector<int> uncertain_tangent;
    const std::vector<int> unknowns = IntrinsicsUnknowns({}, uncertain, &uncertain_tangent);
    double* K_block =
        unknowns.empty() ? nullptr : chain.AddIntrinsics(dataset.cameras[k].params, unknowns);
    if (K_block)
      ceres_problem.AddResidualBlock(UncertainIntrinsicsPrior(dataset.cameras[k], uncertain, 1.0),
                                     nullptr, K_block);
    std::vector<ceres::ResidualBlockId> views;
    for (int v : problem.camera_views[k]) {
      const View& view = problem.views[v];
      std::vector<double*> view_blocks = {T_cam_mount, T_holder_target};
      if (K_block) view_blocks.push_back(K_block);
      views.push_back(ceres_problem.AddResidualBlock(
          ViewReprojectionError::Create(dataset.cameras[k], problem.T_mount_holder[view.pose],
                                        Points(view), options.cauchy_scale_px, K_block != nullptr),
          nullptr, view_blocks));
    }
    out.T_holder_target[k] = ChainProblem::Pose(T_holder_target);
    if (step == JointStep::kCovariance) {
      out.T_cam_mount[k] = ChainProblem::Pose(T_cam_mount);
      ConsiderCovariance covariance(
          K_block ? std::vector<ConsiderCovariance::Coordinates>{{K_block, uncertain_tangent}}
                  : std::vector<ConsiderCovariance::Coordinates>{},
          uncertain.covariance, UncertainIntrinsicsPriorInformation(uncertain, 1.0));
      if (covariance.Compute({{T_cam_mount, T_cam_mount}}, &ceres_problem, options.threads)) {
        const double variance_factor = VarianceFactor(&ceres_problem, views);
        out.T_cam_mount_covariance[k] = Eigen::Matrix<double, 6, 6>(
            covariance.Block(T_cam_mount, T_cam_mount) * variance_factor);
        out.T_cam_mount_intrinsics_shift[k] = covariance.Shift(T_cam_mount, variance_factor);
        out.T_cam_mount_intrinsics_covariance[k] =
            covariance.Consider(T_cam_mount, variance_factor);
      }
      continue;
    }
    const SolverSummary s = Solve(SolverOptions(options, ceres_problem), options, &ceres_problem);
    out.summary.seconds += s.seconds;
    out.summary.iterations += s.iterations;
    out.summary.termination = s.termination;
    out.summary.converged = out.summary.converged && s.converged;
    out.T_cam_mount[k] = ChainProblem::Pose(T_cam_mount);
    out.T_holder_target[k] = ChainProblem::Pose(T_holder_target);
  }
  return out;
}

}  // namespace handeye::internal
