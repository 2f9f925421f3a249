// SPDX-License-Identifier: GPL-2.0-or-later
// The nonlinear refinement's shared parts (refine_internal.h: the solver,
// its mm/deg stopping rule) and the per-camera variant; the paper's joint
// problem is in refine_joint.cc.
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

#include "chain_problem.h"
#include "consider_covariance.h"
#include "cost_functions.h"
#include "covariance.h"
#include "handeye/core/error.h"
#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"
#include "initialisation.h"
#include "intrinsics_internal.h"
#include "problem.h"
#include "refine_internal.h"
#include "refinement.h"

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

}  // namespace

std::shared_ptr<const ViewPoints> Points(const View& view) {
  return std::make_shared<const ViewPoints>(ViewPoints{view.p_target, view.observation->points_px});
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
  out.T_cam_mount_own_intrinsics_shift.resize(dataset.cameras.size());
  out.intrinsics_offset_px.resize(dataset.cameras.size());
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
        if (K_block && !covariance.Held(K_block).empty()) {
          out.intrinsics_offset_px[k] = covariance.Suggested(K_block, variance_factor).head<4>();
          out.T_cam_mount_own_intrinsics_shift[k] =
              covariance.ShiftOf(T_cam_mount, K_block, variance_factor).leftCols<4>();
        }
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
