// SPDX-License-Identifier: GPL-2.0-or-later
// The nonlinear refinement: the paper's joint problem (shared Z, c_rpj + c_cross
// under a Cauchy loss) and the per-camera variant.
#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/product_manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <chrono>
#include <memory>

#include "calibration_internal.h"
#include "handeye/core/cost_functions.h"
#include "handeye/core/error.h"

namespace handeye::internal {
namespace {

using PoseManifold = ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>;

/// Pose blocks that Ceres optimises in place, with stable addresses.
class PoseBlocks {
 public:
  double* Add(const Eigen::Isometry3d& T) {
    blocks_.push_back(std::make_unique<PoseParams>(ToPoseParams(T)));
    return blocks_.back()->data();
  }
  static Eigen::Isometry3d Get(const double* block) { return FromPoseParams(block); }

 private:
  std::vector<std::unique_ptr<PoseParams>> blocks_;
};

void SetPoseManifold(ceres::Problem* problem, double* block) {
  problem->SetManifold(block, new PoseManifold());
}

ceres::Solver::Options SolverOptions(const CalibrationOptions& options, int num_blocks) {
  ceres::Solver::Options solver;
  // The problem has no landmarks, only a few pose blocks: dense normal
  // equations are fastest while the system is small; sparse ones once many
  // cameras make it large and mostly empty (pairs only touch their two cameras).
  solver.linear_solver_type =
      num_blocks <= 80 ? ceres::DENSE_NORMAL_CHOLESKY : ceres::SPARSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = 1e-12;
  solver.gradient_tolerance = 1e-14;
  solver.parameter_tolerance = 1e-12;
  solver.num_threads = options.threads;
  solver.logging_type = ceres::SILENT;
  return solver;
}

SolverSummary Solve(const ceres::Solver::Options& solver, ceres::Problem* problem) {
  ceres::Solver::Summary summary;
  const auto start = std::chrono::steady_clock::now();
  ceres::Solve(solver, problem, &summary);
  SolverSummary out;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.iterations = static_cast<int>(summary.iterations.size()) - 1;
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.termination = ceres::TerminationTypeToString(summary.termination_type);
  if (summary.termination_type == ceres::FAILURE || summary.termination_type == ceres::USER_FAILURE)
    throw SolveError("the nonlinear solver failed: " + summary.message);
  if (!out.converged)
    throw SolveError("the nonlinear solver did not converge in " + std::to_string(out.iterations) +
                     " iterations (" + summary.message + ")");
  return out;
}

}  // namespace

Refinement RefineJoint(const Problem& problem, const Initialisation& init,
                       const CalibrationOptions& options) {
  const Dataset& dataset = *problem.dataset;
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(problem_options);
  ceres::CauchyLoss loss(options.cauchy_scale_px);
  PoseBlocks blocks;

  double* Z = blocks.Add(init.Z);
  ceres_problem.AddParameterBlock(Z, 7);
  SetPoseManifold(&ceres_problem, Z);
  std::vector<double*> X(dataset.cameras.size(), nullptr);
  for (size_t k = 0; k < X.size(); ++k) {
    if (!init.X[k] || problem.camera_views[k].empty()) continue;
    X[k] = blocks.Add(*init.X[k]);
    ceres_problem.AddParameterBlock(X[k], 7);
    SetPoseManifold(&ceres_problem, X[k]);
  }

  // c_rpj: every point of every used view.
  std::vector<std::vector<int>> views_at_pose(dataset.poses.size());
  for (size_t v = 0; v < problem.views.size(); ++v) {
    const View& view = problem.views[v];
    if (!view.used || !X[view.camera]) continue;
    views_at_pose[view.pose].push_back(static_cast<int>(v));
    const Camera& camera = dataset.cameras[view.camera];
    for (size_t i = 0; i < view.p_target.size(); ++i)
      ceres_problem.AddResidualBlock(
          ReprojectionError::Create(camera, problem.M[view.pose], view.p_target[i],
                                    view.observation->points_px[i]),
          &loss, X[view.camera], Z);
  }

  // c_cross: at each pose, for each ordered pair (k, t) of cameras that both
  // detected the target, camera k's points predicted through camera t.
  std::map<std::pair<int, int>, double*> pair_blocks;
  if (options.cross_terms) {
    for (const auto& at_pose : views_at_pose)
      for (int vk : at_pose)
        for (int vt : at_pose) {
          if (vk == vt) continue;
          const View& view_k = problem.views[vk];
          const int k = view_k.camera, t = problem.views[vt].camera;
          double*& T_kt = pair_blocks[{k, t}];
          if (!T_kt) {
            T_kt = blocks.Add(*init.X[k] * init.X[t]->inverse());
            ceres_problem.AddParameterBlock(T_kt, 7);
            SetPoseManifold(&ceres_problem, T_kt);
          }
          const Camera& camera_k = dataset.cameras[k];
          for (size_t i = 0; i < view_k.p_target.size(); ++i)
            ceres_problem.AddResidualBlock(
                CrossReprojectionError::Create(camera_k, problem.M[view_k.pose], view_k.p_target[i],
                                               view_k.observation->points_px[i]),
                &loss, T_kt, X[t], Z);
        }
  }

  const int num_blocks = ceres_problem.NumParameterBlocks();
  Refinement out;
  out.summary = Solve(SolverOptions(options, num_blocks), &ceres_problem);
  out.Z.push_back(PoseBlocks::Get(Z));
  out.X.resize(X.size());
  for (size_t k = 0; k < X.size(); ++k)
    if (X[k]) out.X[k] = PoseBlocks::Get(X[k]);
  for (const auto& [pair, block] : pair_blocks) out.pairs[pair] = PoseBlocks::Get(block);
  return out;
}

Refinement RefinePerCamera(const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& X0,
                           const std::vector<Eigen::Isometry3d>& Z0, const CalibrationOptions& options) {
  const Dataset& dataset = *problem.dataset;
  Refinement out;
  out.X.resize(dataset.cameras.size());
  out.Z = Z0;
  ceres::CauchyLoss loss(options.cauchy_scale_px);
  for (size_t k = 0; k < dataset.cameras.size(); ++k) {
    if (!X0[k] || problem.camera_views[k].empty()) continue;
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem ceres_problem(problem_options);
    PoseBlocks blocks;
    double* X = blocks.Add(*X0[k]);
    double* Z = blocks.Add(Z0[k]);
    for (double* b : {X, Z}) {
      ceres_problem.AddParameterBlock(b, 7);
      SetPoseManifold(&ceres_problem, b);
    }
    for (int v : problem.camera_views[k]) {
      const View& view = problem.views[v];
      for (size_t i = 0; i < view.p_target.size(); ++i)
        ceres_problem.AddResidualBlock(
            ReprojectionError::Create(dataset.cameras[k], problem.M[view.pose], view.p_target[i],
                                      view.observation->points_px[i]),
            &loss, X, Z);
    }
    const SolverSummary s = Solve(SolverOptions(options, 2), &ceres_problem);
    out.summary.seconds += s.seconds;
    out.summary.iterations += s.iterations;
    out.summary.termination = s.termination;
    out.X[k] = PoseBlocks::Get(X);
    out.Z[k] = PoseBlocks::Get(Z);
  }
  out.summary.converged = true;
  return out;
}

}  // namespace handeye::internal
