// SPDX-License-Identifier: GPL-2.0-or-later
// The per-camera strategies of Calibrate(): `per-camera` (a closed form, then
// each camera's reprojection solve with its own T_holder_target) and the
// closed forms on their own, with the σ each can state.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "calibrate_stages.h"
#include "closed_form.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "pose_consensus.h"
#include "pose_manifold.h"
#include "problem.h"
#include "refinement.h"
#include "residuals.h"
#include "solve_rounds.h"

namespace handeye::internal {
namespace {

// One camera's closed-form (T_cam_mount, T_holder_target), or nullopt with the reason.
using CameraSolve = std::function<std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>>(
    int camera, std::string* why)>;

// Per-camera methods: a closed form (`solve`, named `method_name` in
// warnings) on every camera that has the views for it; the others are
// reported, not fatal.
Estimate PerCameraEstimate(const Problem& problem, const CameraSolve& solve,
                           const std::string& method_name, std::vector<Warning>* warnings) {
  const size_t n = problem.camera_views.size();
  Estimate est;
  est.T_cam_mount.resize(n);
  est.T_holder_target.resize(n, Eigen::Isometry3d::Identity());
  est.per_camera_target = true;
  std::vector<Eigen::Isometry3d> solved_T_holder_target;
  for (size_t k = 0; k < n; ++k) {
    if (problem.camera_views[k].empty()) continue;
    std::string why;
    const auto solved = solve(static_cast<int>(k), &why);
    if (!solved) {
      warnings->push_back(CameraWarning(WarningKind::kCameraMethodFailed,
                                        problem.dataset->cameras[k].name,
                                        "camera '" + problem.dataset->cameras[k].name +
                                            "' not calibrated by " + method_name + ": " + why));
      continue;
    }
    est.T_cam_mount[k] = solved->first;
    est.T_holder_target[k] = solved->second;
    solved_T_holder_target.push_back(solved->second);
  }
  if (solved_T_holder_target.empty())
    throw SolveError("method '" + method_name + "' could not calibrate any camera (see warnings)");
  est.shared_T_holder_target = MeanTransform(solved_T_holder_target);
  return est;
}

/// The per-camera reprojection solve from `est` (each camera with its own
/// T_holder_target over all its views), made robust (RobustSolve); `est`
/// ends at the solution.
Refinement SolvePerCamera(Problem* problem, const CalibrationOptions& options, Estimate* est,
                          std::vector<Warning>* warnings) {
  const double first_scale =
      std::max(1.0, 3.0 * ResidualSigmaPx(*problem, est->T_cam_mount, est->T_holder_target));
  const Refinement refined = RobustSolve(
      problem, options, first_scale,
      [&](double scale) {
        Refinement r = RefinePerCamera(*problem, est->T_cam_mount, est->T_holder_target,
                                       AtLossScale(options, scale));
        for (size_t k = 0; k < r.T_cam_mount.size(); ++k)
          if (r.T_cam_mount[k]) est->T_cam_mount[k] = r.T_cam_mount[k];
        est->T_holder_target = r.T_holder_target;
        return r;
      },
      warnings);
  est->T_cam_mount = refined.T_cam_mount;
  est->T_holder_target = refined.T_holder_target;
  return refined;
}

/// Each camera's covariance under the per-camera model at `est` (its
/// solution, solved with loss scale `cauchy_scale_px`).
CameraCovariance PerCameraCovariance(const Problem& problem, const Estimate& est,
                                     const CalibrationOptions& options, double cauchy_scale_px) {
  const Refinement covariance =
      RefinePerCamera(problem, est.T_cam_mount, est.T_holder_target,
                      AtLossScale(options, cauchy_scale_px), JointStep::kCovariance);
  CameraCovariance out;
  for (size_t k = 0; k < covariance.T_cam_mount_covariance.size(); ++k)
    if (est.T_cam_mount[k]) out.Add(covariance, k);
  return out;
}

/// A closed form's covariance. A closed form is no minimum of the images'
/// residuals, so no covariance of its own exists; its error is the
/// reprojection solve's (from the same views, started at the closed form)
/// plus the distance d between the two, whose one sample dᵀ·d stands for the
/// closed form's extra error (robot noise of 0.5 mm costs a closed form
/// millimetres, the reprojection solve a fraction): Cov = Cov_solve + d dᵀ.
/// The result stays the closed form's; the solve is only measured.
CameraCovariance ClosedFormCovariance(const Problem& problem, const Estimate& closed_form,
                                      const CalibrationOptions& options) {
  Problem copy = problem;  // the solve's view exclusions are not the closed form's
  Estimate solved = closed_form;
  std::vector<Warning> ignored;
  CameraCovariance out;
  try {
    const Refinement refined = SolvePerCamera(&copy, options, &solved, &ignored);
    out = PerCameraCovariance(copy, solved, options, refined.summary.cauchy_scale_px);
  } catch (const SolveError&) {
    return out;  // no solve to measure it by: no σ
  }
  const PoseManifold manifold;
  for (auto& [k, covariance] : out.covariance) {
    const PoseParams at = ToPoseParams(*solved.T_cam_mount[k]),
                     cf = ToPoseParams(*closed_form.T_cam_mount[k]);
    Eigen::Matrix<double, 6, 1> d;
    manifold.Minus(cf.data(), at.data(), d.data());
    covariance += d * d.transpose();
  }
  return out;
}

}  // namespace

void SolvePerCameraMethod(Calibration* c) {
  // Each camera on its own: a closed form that prints nothing (on diverse
  // views) then the reprojection solve with its own T_holder_target over all views.
  const Problem diverse = WithDiverseViews(c->problem, 12);
  c->est = PerCameraEstimate(
      diverse,
      [&](int camera, std::string* why) {
        std::string chosen;
        return SilentClosedFormHandEye(diverse, camera, &chosen, why);
      },
      MethodName(c->options.method), &c->result.warnings);
  const Refinement refined = SolvePerCamera(&c->problem, c->options, &c->est, &c->result.warnings);
  std::vector<Eigen::Isometry3d> solved;
  for (size_t k = 0; k < c->est.T_cam_mount.size(); ++k)
    if (c->est.T_cam_mount[k]) solved.push_back(c->est.T_holder_target[k]);
  c->est.shared_T_holder_target = MeanTransform(solved);
  c->result.solver = refined.summary;
  c->camera_covariance =
      PerCameraCovariance(c->problem, c->est, c->options, refined.summary.cauchy_scale_px);
}

void SolveClosedFormMethod(Calibration* c) {
  c->est = PerCameraEstimate(
      c->problem,
      [&](int camera, std::string* why) {
        return ClosedFormHandEye(c->problem, camera, c->options.method, why);
      },
      MethodName(c->options.method), &c->result.warnings);
  c->result.solver.converged = true;
  c->result.solver.termination = "CLOSED_FORM";
  c->camera_covariance = ClosedFormCovariance(c->problem, c->est, c->options);
}

}  // namespace handeye::internal
