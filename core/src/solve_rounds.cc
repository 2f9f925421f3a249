// SPDX-License-Identifier: GPL-2.0-or-later
// The rounds around the nonlinear solve: solve, exclude the views far off the
// solution, set the loss scale from the residuals, solve again; and the
// leave-one-pose-out validation.
#include "solve_rounds.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <vector>

#include "detection_noise.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "problem.h"
#include "refinement.h"
#include "residuals.h"
#include "view_consensus.h"

namespace handeye::internal {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

/// Per robot pose, the indices of its used views.
std::vector<std::vector<int>> UsedViewsAtPose(const Problem& problem) {
  std::vector<std::vector<int>> views_at_pose(problem.T_mount_holder.size());
  for (size_t v = 0; v < problem.views.size(); ++v)
    if (problem.views[v].used) views_at_pose[problem.views[v].pose].push_back(static_cast<int>(v));
  return views_at_pose;
}

/// The joint solve (from `init`, under `robot`) without the views `left_out`;
/// nullopt when it cannot be solved.
std::optional<Refinement> SolveWithout(const Problem& problem, const std::vector<int>& left_out,
                                       const Initialisation& init,
                                       const CalibrationOptions& options,
                                       const std::optional<RobotPrior>& robot) {
  Problem fold = problem;
  for (int v : left_out) fold.views[v].used = false;
  IndexUsedViews(&fold);
  try {
    return RefineJoint(fold, init, options, robot);
  } catch (const SolveError&) {
    return std::nullopt;
  }
}

}  // namespace

TargetPoses TargetPosesOf(const Refinement& refined, size_t num_cameras) {
  if (refined.T_holder_target.size() == num_cameras) return refined.T_holder_target;
  return TargetPoses(num_cameras, refined.T_holder_target.front());
}

Refinement RobustSolve(Problem* problem, const CalibrationOptions& options, double first_scale,
                       const std::function<Refinement(double scale_px)>& solve,
                       std::vector<Warning>* warnings) {
  constexpr int kMaxRounds = 5;
  const size_t n = problem->camera_views.size();
  const bool fixed_scale = options.cauchy_scale_px > 0;
  double scale = fixed_scale ? options.cauchy_scale_px : first_scale;
  SolverSummary total;
  Refinement refined;
  int used_before = 0;
  for (const auto& views : problem->camera_views) used_before += static_cast<int>(views.size());
  for (int round = 1;; ++round) {
    refined = solve(scale);
    total.seconds += refined.summary.seconds;
    total.iterations += refined.summary.iterations;
    const TargetPoses T_holder_target = TargetPosesOf(refined, n);
    std::vector<int> off;
    if (options.reject_views && round < kMaxRounds)
      off = ViewsOffTheSolution(*problem, refined.T_cam_mount, T_holder_target);
    int used = 0;
    for (const auto& views : problem->camera_views) used += static_cast<int>(views.size());
    if (3 * static_cast<int>(off.size()) > used_before) {
      // So many views cannot all be bad records: the model itself (intrinsics,
      // target size) or the robot poses as a whole are off. Keep them and say so.
      warnings->push_back(
          GeneralWarning(WarningKind::kManyViewsOff,
                         std::to_string(off.size()) + " of " + std::to_string(used) +
                             " views lie far outside the residuals of the others; they were kept: "
                             "check the intrinsics, the target's size and the robot pose units"));
      off.clear();
    }
    for (int v : off) {
      View& view = problem->views[v];
      double max_px = 0;
      const double rms = ViewRms(ViewErrors(*problem, view, *refined.T_cam_mount[view.camera],
                                            T_holder_target[view.camera]),
                                 &max_px);
      std::ostringstream why;
      why.precision(3);
      why << "it disagrees with the calibration of the other views (RMS " << rms
          << " px, far outside their residuals): the robot record or the image is off";
      view.used = false;
      view.inconsistent = true;
      view.rejected_because = why.str();
    }
    if (!off.empty()) IndexUsedViews(problem);
    double new_scale = scale;
    if (!fixed_scale)
      new_scale =
          std::max(1.0, 3.0 * ResidualSigmaPx(*problem, refined.T_cam_mount, T_holder_target));
    const bool scale_settled = std::abs(new_scale - scale) <= 0.1 * scale;
    if ((off.empty() && scale_settled) || round == kMaxRounds) {
      total.rounds = round;
      break;
    }
    scale = new_scale;
  }
  total.converged = refined.summary.converged;
  total.termination = refined.summary.termination;
  total.cauchy_scale_px = scale;
  refined.summary = total;
  return refined;
}

void CrossValidate(const Problem& problem, const Initialisation& init,
                   const CalibrationOptions& options, const std::optional<RobotPrior>& robot,
                   std::vector<CameraResult::CrossValidation>* out) {
  const size_t n = problem.camera_views.size();
  out->assign(n, {});
  std::vector<double> sq(n, 0.0), moved_sq(n, 0.0), turned_sq(n, 0.0);
  std::vector<int> points(n, 0), solves(n, 0);
  const std::vector<std::vector<int>> views_at_pose = UsedViewsAtPose(problem);
  for (size_t j = 0; j < views_at_pose.size(); ++j) {
    if (views_at_pose[j].empty()) continue;
    const std::optional<Refinement> solved =
        SolveWithout(problem, views_at_pose[j], init, options, robot);
    if (!solved) continue;  // a fold that cannot be solved tells nothing about the others
    const Refinement& r = *solved;
    for (int v : views_at_pose[j]) {
      const View& view = problem.views[v];
      if (!r.T_cam_mount[view.camera]) continue;
      for (double e :
           ViewErrors(problem, view, *r.T_cam_mount[view.camera], r.T_holder_target[0])) {
        sq[view.camera] += e * e;
        ++points[view.camera];
      }
      ++(*out)[view.camera].folds;
    }
    for (size_t k = 0; k < n; ++k) {
      if (!r.T_cam_mount[k] || !init.T_cam_mount[k]) continue;
      const Eigen::Isometry3d a = r.T_cam_mount[k]->inverse(), b = init.T_cam_mount[k]->inverse();
      moved_sq[k] += (a.translation() - b.translation()).squaredNorm();
      turned_sq[k] += std::pow(RotationDistance(a.rotation(), b.rotation()), 2);
      ++solves[k];
    }
  }
  for (size_t k = 0; k < n; ++k) {
    auto& c = (*out)[k];
    if (points[k]) c.held_out_rms_px = std::sqrt(sq[k] / points[k]);
    if (solves[k]) {
      c.position_spread_mm = 1000.0 * std::sqrt(moved_sq[k] / solves[k]);
      c.rotation_spread_deg = kRadToDeg * std::sqrt(turned_sq[k] / solves[k]);
    }
  }
}

std::vector<FoldError> HeldOutErrors(const Problem& problem, const Initialisation& init,
                                     const CalibrationOptions& options,
                                     const std::optional<RobotPrior>& robot, int folds) {
  const std::vector<std::vector<int>> views_at_pose = UsedViewsAtPose(problem);
  std::vector<int> poses;
  for (size_t j = 0; j < views_at_pose.size(); ++j)
    if (!views_at_pose[j].empty()) poses.push_back(static_cast<int>(j));
  const std::vector<double> weight = CameraWeights(problem);
  std::vector<FoldError> out(folds);
  for (int f = 0; f < folds; ++f) {
    std::vector<int> left_out;
    for (size_t i = f; i < poses.size(); i += folds)
      left_out.insert(left_out.end(), views_at_pose[poses[i]].begin(),
                      views_at_pose[poses[i]].end());
    const std::optional<Refinement> solved = SolveWithout(problem, left_out, init, options, robot);
    if (!solved) continue;  // a fold that cannot be solved predicts nothing
    const Refinement& r = *solved;
    // The left-out views seen through the fold's own intrinsics (ViewErrors
    // reads the cameras alone; the views keep pointing at their observations).
    Dataset refined;
    refined.cameras = problem.dataset->cameras;
    for (size_t k = 0; k < refined.cameras.size() && k < r.intrinsics.size(); ++k)
      refined.cameras[k].params = r.intrinsics[k];
    Problem scored = problem;
    scored.dataset = &refined;
    out[f].solved = true;
    for (int v : left_out) {
      const View& view = problem.views[v];
      if (!r.T_cam_mount[view.camera]) continue;
      const double w = weight[view.camera];
      for (double e : ViewErrors(scored, view, *r.T_cam_mount[view.camera], r.T_holder_target[0])) {
        out[f].sum_sq_px += w * w * e * e;
        ++out[f].points;
      }
    }
  }
  return out;
}

}  // namespace handeye::internal
