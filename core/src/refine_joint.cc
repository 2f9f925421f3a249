// SPDX-License-Identifier: GPL-2.0-or-later
// The paper's joint problem (shared T_holder_target, c_rpj + c_cross under a
// Cauchy loss), built on a ChainProblem in steps: the poses, the intrinsics,
// the views and their cross terms; solved with the Schur ordering below.
#include <ceres/loss_function.h>
#include <ceres/ordered_groups.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <algorithm>
#include <map>
#include <memory>

#include "chain_problem.h"
#include "cost_functions.h"
#include "detection_noise.h"
#include "initialisation.h"
#include "intrinsics_internal.h"
#include "problem.h"
#include "refine_internal.h"
#include "refinement.h"
#include "robot_error.h"

namespace handeye::internal {
namespace {

/// The joint problem as RefineJoint builds it: what it reads, the chain and
/// its blocks (nullptr where a camera or pose has none).
struct JointBuild {
  JointBuild(const Problem& p, const Initialisation& i, const CalibrationOptions& o,
             const std::optional<RobotPrior>& r, ChainProblem& c)
      : problem(p), init(i), options(o), robot(r), chain(c) {}
  const Problem& problem;
  const Initialisation& init;
  const CalibrationOptions& options;
  const std::optional<RobotPrior>& robot;
  ChainProblem& chain;
  /// The robot pose blocks stay at the reported poses (JointStep::kCovarianceRobotHeld).
  bool robot_held = false;
  double* T_holder_target = nullptr;
  std::vector<double*> T_cam_mount, K, T_mount_holder;
  std::map<std::pair<int, int>, double*> pairs;  // (k, t) -> T_camk_mount_via_t
  std::vector<RobotPoseBlock> robot_poses;
  std::vector<ceres::ResidualBlockId> direct;  // c_rpj, one per view
  std::vector<std::vector<ceres::ResidualBlockId>> at_pose;  // each robot pose's residual blocks
  // For the covariance, the given intrinsics that stay held are uncertain
  // inputs too (ConsiderCovariance): unknowns of the problem under a prior.
  std::vector<ConsiderCovariance::Coordinates> uncertain_coordinates;
  std::vector<Eigen::MatrixXd> uncertain_covariances, uncertain_prior_information;
  /// Per camera, its pixel residuals' weight (CameraWeights).
  std::vector<double> weight = CameraWeights(problem);
};

/// T_holder_target and each camera with views (held where asked).
void AddPoses(JointBuild* b) {
  const size_t n = b->problem.dataset->cameras.size();
  b->T_holder_target = b->chain.AddPose(b->init.T_holder_target);
  b->T_cam_mount.assign(n, nullptr);
  for (size_t k = 0; k < n; ++k) {
    if (!b->init.T_cam_mount[k] || b->problem.camera_views[k].empty()) continue;
    b->T_cam_mount[k] =
        b->chain.AddPose(*b->init.T_cam_mount[k],
                         k < b->init.fixed_T_cam_mount.size() && b->init.fixed_T_cam_mount[k]);
  }
}

/// Free intrinsics: one block of 18 per camera, the fixed ones held by a
/// subset manifold; under their prior where refined, and (the covariance
/// step) the held given ones as uncertain inputs under theirs.
void AddIntrinsics(JointBuild* b, JointStep step) {
  const Dataset& dataset = *b->problem.dataset;
  ceres::Problem& ceres_problem = b->chain.problem();
  b->K.assign(dataset.cameras.size(), nullptr);
  for (size_t k = 0; k < dataset.cameras.size(); ++k) {
    if (!b->T_cam_mount[k]) continue;
    const std::vector<int> free =
        k < b->init.free_intrinsics.size() ? b->init.free_intrinsics[k] : std::vector<int>{};
    const UncertainIntrinsics uncertain =
        step != JointStep::kSolve
            ? UncertainGivenIntrinsics(dataset.cameras[k], free, b->options.intrinsics_sigma)
            : UncertainIntrinsics{};
    std::vector<int> uncertain_tangent;
    const std::vector<int> unknowns = IntrinsicsUnknowns(free, uncertain, &uncertain_tangent);
    if (unknowns.empty()) continue;
    b->K[k] = b->chain.AddIntrinsics(dataset.cameras[k].params, unknowns);
    const double sigma_px = b->init.pixel_sigma_px;
    if (!free.empty())
      ceres_problem.AddResidualBlock(IntrinsicsPrior(b->init.given_cameras[k], free, sigma_px),
                                     nullptr, b->K[k]);
    if (uncertain.params.empty()) continue;
    ceres_problem.AddResidualBlock(
        UncertainIntrinsicsPrior(dataset.cameras[k], uncertain, sigma_px), nullptr, b->K[k]);
    b->uncertain_coordinates.push_back({b->K[k], uncertain_tangent});
    b->uncertain_covariances.push_back(uncertain.covariance);
    b->uncertain_prior_information.push_back(
        UncertainIntrinsicsPriorInformation(uncertain, sigma_px));
  }
}

/// With a robot prior, each robot pose with a used view is a block, tied to
/// the reported pose by its prior; made when a view first needs it.
double* RobotPoseBlockOf(JointBuild* b, int j) {
  if (b->T_mount_holder[j]) return b->T_mount_holder[j];
  const Initialisation& init = b->init;
  ceres::ResidualBlockId prior;
  const bool started =
      !b->robot_held && j < static_cast<int>(init.T_mount_holder.size()) && init.T_mount_holder[j];
  b->T_mount_holder[j] = b->chain.AddRobotPose(
      started ? *init.T_mount_holder[j] : b->problem.T_mount_holder[j],
      b->problem.dataset->poses[j], b->problem.dataset->setup, *b->robot, &prior);
  b->robot_poses.push_back({b->T_mount_holder[j], prior});
  b->at_pose[j].push_back(prior);
  return b->T_mount_holder[j];
}

/// One view's reprojection cost through camera block `camera_block`
/// (T_camk_mount, direct or via t).
ceres::ResidualBlockId AddView(JointBuild* b, const View& view, int k, double* camera_block,
                               std::shared_ptr<const ViewPoints> view_points) {
  const Camera& camera = b->problem.dataset->cameras[k];
  // The residuals are weighed by w under the loss scale a: w²·ρ_{a/w}(s) = ρ_a(w²s).
  const double weight = b->weight[k];
  const double scale = b->options.cauchy_scale_px / weight;
  const bool free_intrinsics = b->K[k] != nullptr;
  std::vector<double*> blocks = {camera_block};
  ceres::CostFunction* cost;
  if (b->robot) {
    cost = ViewReprojectionWithRobotError::Create(camera, std::move(view_points), scale,
                                                  free_intrinsics);
    blocks.push_back(RobotPoseBlockOf(b, view.pose));
  } else {
    cost = ViewReprojectionError::Create(camera, b->problem.T_mount_holder[view.pose],
                                         std::move(view_points), scale, free_intrinsics);
  }
  blocks.push_back(b->T_holder_target);
  if (free_intrinsics) blocks.push_back(b->K[k]);
  ceres::LossFunction* loss =
      weight == 1.0 ? nullptr
                    : new ceres::ScaledLoss(nullptr, weight * weight, ceres::TAKE_OWNERSHIP);
  const ceres::ResidualBlockId id = b->chain.problem().AddResidualBlock(cost, loss, blocks);
  b->at_pose[view.pose].push_back(id);
  return id;
}

/// c_rpj: every point of every used view (one block per view, the loss per
/// point); then c_cross: at each pose, for each ordered pair (k, t) of
/// cameras that both detected the target, camera k's points predicted
/// through camera t: π_k(T_camk_camt · T_camt_mount · T_mount_holder[j] ·
/// T_holder_target · p). T_camk_camt is free (one block per pair), so the
/// term is solved in the variable T_camk_mount_via_t = T_camk_camt ·
/// T_camt_mount (camera k's pose as seen through camera t; the paper's Y_kt)
/// and T_camk_camt = T_camk_mount_via_t · T_mount_camt is read back after the
/// solve: (T_camk_camt, T_camt_mount) -> (T_camk_mount_via_t, T_camt_mount)
/// is a bijection, so the cost, its minimum and the minimiser are the
/// paper's, while each c_cross block touches two blocks instead of three (a
/// third less Jacobian to store, evaluate and eliminate). A view's points are
/// shared by its c_rpj block and its c_cross blocks.
void AddViews(JointBuild* b) {
  const Problem& problem = b->problem;
  b->T_mount_holder.assign(problem.dataset->poses.size(), nullptr);
  b->at_pose.assign(problem.dataset->poses.size(), {});
  std::vector<std::vector<int>> views_at_pose(problem.dataset->poses.size());
  std::vector<std::shared_ptr<const ViewPoints>> points(problem.views.size());
  for (size_t v = 0; v < problem.views.size(); ++v) {
    const View& view = problem.views[v];
    if (!view.used || !b->T_cam_mount[view.camera]) continue;
    views_at_pose[view.pose].push_back(static_cast<int>(v));
    points[v] = Points(view);
    b->direct.push_back(AddView(b, view, view.camera, b->T_cam_mount[view.camera], points[v]));
  }
  if (!b->options.cross_terms) return;
  for (const auto& here : views_at_pose)
    for (int vk : here)
      for (int vt : here) {
        if (vk == vt) continue;
        const View& view_k = problem.views[vk];
        const int k = view_k.camera, t = problem.views[vt].camera;
        double*& T_camk_mount_via_t = b->pairs[{k, t}];
        // T_camk_camt starts at T_camk_mount · T_mount_camt (this block at
        // T_camk_mount) unless the start names it.
        if (!T_camk_mount_via_t) {
          const auto start = b->init.T_camk_camt.find({k, t});
          T_camk_mount_via_t = b->chain.AddPose(start == b->init.T_camk_camt.end()
                                                    ? *b->init.T_cam_mount[k]
                                                    : start->second * *b->init.T_cam_mount[t]);
        }
        AddView(b, view_k, k, T_camk_mount_via_t, points[vk]);
      }
}

/// Every residual block touches T_holder_target and exactly one other block
/// (T_camk_mount, direct or via t), so all of those are eliminated block by
/// block (Schur complement, built on all threads) and only T_holder_target's
/// 6×6 system is left to factor. Forming JᵀJ of the whole Jacobian instead
/// (sparse normal Cholesky) ran on one thread and copied the Jacobian, ~10x
/// larger with the cross blocks than the c_rpj part, at every step to append
/// the LM diagonal. With robot pose blocks, each residual block touches one
/// of those too, so either set can be eliminated; the larger one is, and the
/// other with T_holder_target forms the dense reduced system. Eliminating the
/// robot poses always left 32 cameras and their pairs (≈ 3000 unknowns) to a
/// dense Cholesky at every step: 186 s for 32 cameras × 50 poses with a
/// robot of 0.5 mm, 74 % of it in that factorisation.
ceres::Solver::Options JointSolverOptions(const JointBuild& b) {
  ceres::Solver::Options solver = SolverOptions(b.options, b.chain.problem());
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  const auto robot_blocks = std::count_if(b.T_mount_holder.begin(), b.T_mount_holder.end(),
                                          [](const double* block) { return block != nullptr; });
  const auto camera_blocks = std::count_if(b.T_cam_mount.begin(), b.T_cam_mount.end(),
                                           [](const double* block) { return block != nullptr; }) +
                             static_cast<long>(b.pairs.size());
  const int camera_group = robot_blocks > camera_blocks ? 1 : 0;
  for (double* block : b.T_cam_mount)
    if (block) ordering->AddElementToGroup(block, camera_group);
  for (const auto& [pair, block] : b.pairs) ordering->AddElementToGroup(block, camera_group);
  for (double* block : b.T_mount_holder)
    if (block) ordering->AddElementToGroup(block, 1 - camera_group);
  ordering->AddElementToGroup(b.T_holder_target, 1);
  for (double* block : b.K)
    if (block) ordering->AddElementToGroup(block, 1);
  solver.linear_solver_type = ceres::DENSE_SCHUR;
  solver.linear_solver_ordering = ordering;
  // The closed-form start is close, so the first steps can be near
  // Gauss-Newton: with Ceres' default radius (1e4) the damping held the
  // convergence back by one or two iterations (16 and 32 cameras: 6-7 -> 5)
  // on the way to the same minimum.
  solver.initial_trust_region_radius = 1e6;
  return solver;
}

/// Each robot pose block's tangent coordinates and the covariance its prior
/// stands for: the prior's residuals are its σ-scaled errors times the
/// detection σ (RobotPosePrior), so with J their Jacobian in the block's
/// tangent space the error's covariance there is σ_px² (JᵀJ)⁻¹.
void HoldRobotPoses(const JointBuild& b, ConsiderCovariance* covariance) {
  std::vector<ConsiderCovariance::Coordinates> coordinates;
  std::vector<Eigen::MatrixXd> sigmas;
  for (const RobotPoseBlock& pose : b.robot_poses) {
    const Eigen::Matrix<double, 6, 6> J = PriorJacobian(b.chain.problem(), pose);
    const double pixel_sigma = b.robot->pixel_sigma_px;
    coordinates.push_back({pose.pose, {0, 1, 2, 3, 4, 5}});
    sigmas.push_back(pixel_sigma * pixel_sigma *
                     (J.transpose() * J).inverse());
  }
  covariance->HoldIndependent(coordinates, BlockDiagonal(sigmas));
}

/// The blocks' values into `out`: T_holder_target, the cameras, the pairs
/// (T_camk_camt = T_camk_mount_via_t · T_mount_camt), the intrinsics and the
/// robot poses.
void ReadSolution(const JointBuild& b, Refinement* out) {
  const Dataset& dataset = *b.problem.dataset;
  out->T_holder_target.push_back(ChainProblem::Pose(b.T_holder_target));
  out->T_cam_mount.resize(b.T_cam_mount.size());
  for (size_t k = 0; k < b.T_cam_mount.size(); ++k)
    if (b.T_cam_mount[k]) out->T_cam_mount[k] = ChainProblem::Pose(b.T_cam_mount[k]);
  for (const auto& [pair, T_camk_mount_via_t] : b.pairs)
    out->pairs[pair] =
        ChainProblem::Pose(T_camk_mount_via_t) * out->T_cam_mount[pair.second]->inverse();
  out->intrinsics.resize(dataset.cameras.size());
  for (size_t k = 0; k < dataset.cameras.size(); ++k) {
    out->intrinsics[k] = dataset.cameras[k].params;
    if (b.K[k]) std::copy(b.K[k], b.K[k] + out->intrinsics[k].size(), out->intrinsics[k].begin());
  }
  out->T_mount_holder.resize(b.T_mount_holder.size());
  for (size_t j = 0; j < b.T_mount_holder.size(); ++j)
    if (b.T_mount_holder[j]) out->T_mount_holder[j] = ChainProblem::Pose(b.T_mount_holder[j]);
}

}  // namespace

Refinement RefineJoint(const Problem& problem, const Initialisation& init,
                       const CalibrationOptions& options, const std::optional<RobotPrior>& robot,
                       JointStep step) {
  // T_holder_target, the cameras, the robot poses, the pairs (k, t); the intrinsics.
  const size_t n_cameras = problem.dataset->cameras.size();
  ChainProblem chain(1 + n_cameras + problem.dataset->poses.size() + n_cameras * n_cameras,
                     n_cameras);
  JointBuild b(problem, init, options, robot, chain);
  b.robot_held = step == JointStep::kCovarianceRobotHeld && robot;
  AddPoses(&b);
  AddIntrinsics(&b, step);
  AddViews(&b);
  Refinement out;
  if (step == JointStep::kSolve)
    out.summary = Solve(JointSolverOptions(b), options, &chain.problem());
  ReadSolution(b, &out);
  if (step != JointStep::kSolve) {
    ConsiderCovariance covariance(b.uncertain_coordinates, BlockDiagonal(b.uncertain_covariances),
                                  BlockDiagonal(b.uncertain_prior_information));
    if (b.robot_held) HoldRobotPoses(b, &covariance);
    SolutionCovariance(&chain.problem(), b.T_cam_mount, b.T_holder_target, b.K, b.direct, b.at_pose,
                       b.robot_held ? std::nullopt : robot, b.robot_poses, &covariance,
                       options.threads, &out);
  }
  return out;
}

}  // namespace handeye::internal
