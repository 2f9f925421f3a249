// SPDX-License-Identifier: GPL-2.0-or-later
// Calibrate(): the calibration as named stages over one state
// (calibrate_stages.h): the cameras and views prepared, the method's
// strategy (calibrate_joint.cc, calibrate_per_camera.cc), then the views
// explained, the result filled, the intrinsics checked, σ and the diagnosis.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>
#include <utility>

#include "calibrate_stages.h"
#include "detection_noise.h"
#include "diagnostics_internal.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "intrinsics_internal.h"
#include "motion_diversity.h"
#include "pose_uncertainty.h"
#include "problem.h"
#include "setup_mistakes.h"
#include "view_consensus.h"

namespace handeye {
namespace internal {

CalibrationOptions AtLossScale(const CalibrationOptions& options, double scale_px) {
  CalibrationOptions at = options;
  at.cauchy_scale_px = scale_px;
  return at;
}

std::vector<unsigned> UnrefinedIntrinsics(const std::vector<std::vector<int>>& free_intrinsics,
                                          size_t num_cameras) {
  std::vector<unsigned> check(num_cameras, kFocal | kPrincipalPoint);
  for (size_t k = 0; k < free_intrinsics.size() && k < num_cameras; ++k)
    for (int p : free_intrinsics[k]) {
      if (p == 0) check[k] &= ~unsigned(kFocal);
      if (p == 2) check[k] &= ~unsigned(kPrincipalPoint);
    }
  return check;
}

}  // namespace internal

namespace {

using internal::Calibration;
using internal::Estimate;
using internal::Problem;
using internal::View;

// Why a camera's (camera < 0: every camera's) detected views were unusable,
// for the message that says so: when most of them fit no plane pose (PnP
// through the given intrinsics), the intrinsics or the distortion are the
// likely culprit, not the robot or the target.
std::string NoPlanePoseHint(const Problem& problem, int camera) {
  // SolvePnpAnySide's reason (calibration_problem.cc).
  static const std::string kNoPlanePose = "the detected points fit no plane pose";
  int views = 0, no_pose = 0;
  for (const View& view : problem.views) {
    if (camera >= 0 && view.camera != camera) continue;
    ++views;
    no_pose += view.rejected_because.rfind(kNoPlanePose, 0) == 0 ? 1 : 0;
  }
  if (no_pose == 0 || 2 * no_pose < views) return "";
  return " (" + std::to_string(no_pose) + " of " + std::to_string(views) +
         " detected views fit no plane pose through " +
         (camera >= 0 ? "the camera's" : "their cameras'") +
         " intrinsics and distortion: these look wrong; check fx, fy, cx, cy and the distortion "
         "coefficients, or leave the intrinsics out to estimate them)";
}

// The result's views and cameras as the solution leaves them; their
// residuals and the metrics come from DiagnoseSolution.
void FillResult(const Problem& problem, const Estimate& est, CalibrationResult* result) {
  const Dataset& dataset = *problem.dataset;
  for (const View& view : problem.views) {
    ViewResult vr;
    vr.pose_id = view.observation->pose_id;
    vr.camera = view.observation->camera;
    vr.num_points = static_cast<int>(view.p_target.size());
    vr.used = view.used;
    vr.rejected_because = view.rejected_because;
    vr.flipped = view.flipped;
    result->views.push_back(vr);
  }
  for (size_t k = 0; k < dataset.cameras.size(); ++k) {
    CameraResult cam;
    cam.name = dataset.cameras[k].name;
    cam.calibrated = est.T_cam_mount[k].has_value();
    for (const View& view : problem.views)
      if (view.camera == static_cast<int>(k)) (view.used ? cam.views : cam.views_rejected) += 1;
    if (cam.calibrated) {
      cam.T_cam = est.T_cam_mount[k]->inverse();
      if (est.per_camera_target) cam.own_T_target = est.T_holder_target[k];
    } else if (cam.views == 0 && cam.views_rejected == 0) {
      result->warnings.push_back(
          CameraWarning(WarningKind::kCameraNotSeen, cam.name,
                        "camera '" + cam.name + "' never saw the target: not calibrated"));
    } else if (cam.views == 0) {
      result->warnings.push_back(
          CameraWarning(WarningKind::kCameraNoUsableViews, cam.name,
                        "camera '" + cam.name + "': the target was detected in " +
                            std::to_string(cam.views_rejected) + " views, but none was usable" +
                            NoPlanePoseHint(problem, static_cast<int>(k)) + ": not calibrated"));
    }
    result->cameras.push_back(cam);
  }
  result->T_target = est.shared_T_holder_target;
}

/// A note per camera that detects the target clearly worse or better than
/// the others, and so weighs differently in the joint solve (CameraWeights).
std::vector<std::string> CameraNoiseNotes(const Problem& problem) {
  const std::vector<double> sigma = internal::CameraSigmasPx(problem),
                            weight = internal::CameraWeights(problem);
  std::vector<std::string> notes;
  for (size_t k = 0; k < sigma.size(); ++k) {
    if (weight[k] == 1.0) continue;
    const double all = sigma[k] * weight[k];
    std::ostringstream note;
    note.precision(2);
    note << "camera '" << problem.dataset->cameras[k].name << "' detects the target with σ "
         << sigma[k] << " px, " << sigma[k] / all << "× the " << all
         << " px of all views: its residuals weigh " << weight[k]
         << "× theirs in the joint solve (blur, focus, exposure, resolution or distance set a "
            "camera's σ)";
    notes.push_back(note.str());
  }
  return notes;
}

/// A note naming the views the robot-motion vote numbered the other way
/// round; empty when there are none.
std::string FlippedViewsNote(const Problem& problem) {
  std::string list;
  int count = 0;
  for (const View& view : problem.views)
    if (view.flipped)
      list += (count++ ? ", " : "") + view.observation->pose_id + "/" + view.observation->camera;
  if (!count) return "";
  return std::to_string(count) + " view" + (count > 1 ? "s" : "") +
         " of the 180°-ambiguous board were numbered half a turn round from the others (no "
         "detector "
         "can tell); the robot's motions say so, and they were used with their ids reversed "
         "(id -> N - 1 - id; `flipped` in the views); pose/camera: " +
         list;
}

/// The warning for views left out, one each, and one for all those seen too
/// obliquely (common on a camera network: boards turned away from a camera).
void ViewsLeftOutWarnings(const Problem& problem, std::vector<Warning>* warnings) {
  std::ostringstream oblique;
  int num_oblique = 0;
  for (size_t i = 0; i < problem.views.size(); ++i) {
    const View& view = problem.views[i];
    if (view.used) continue;
    if (view.oblique_deg > 0) {
      oblique << (num_oblique++ ? ", " : "") << view.observation->pose_id << "/"
              << view.observation->camera << " (" << std::lround(view.oblique_deg) << ")";
      continue;
    }
    Warning left_out =
        CameraWarning(WarningKind::kViewLeftOut, view.observation->camera,
                      "view of pose '" + view.observation->pose_id + "' by camera '" +
                          view.observation->camera + "' left out: " + view.rejected_because);
    left_out.pose = view.observation->pose_id;
    left_out.view = static_cast<int>(i);  // FillResult lists the views in the problem's order
    warnings->push_back(std::move(left_out));
  }
  if (num_oblique)
    warnings->push_back(
        GeneralWarning(WarningKind::kObliqueViewsLeftOut,
                       std::to_string(num_oblique) + " view" + (num_oblique > 1 ? "s" : "") +
                           " left out, the target seen more than " +
                           std::to_string(std::lround(internal::kMaxViewAngleDeg)) +
                           " deg from face-on (too squeezed for a good pose); pose/camera (deg): " +
                           oblique.str()));
}

}  // namespace

namespace internal {

/// Stage 1: the cameras as the solver sees them, intrinsics estimated from
/// the views where the dataset gives none (the joint solve refines them).
void PrepareCameras(Calibration* c) {
  const size_t num_cameras = c->dataset.cameras.size();
  c->estimated.assign(num_cameras, false);
  for (size_t k = 0; k < num_cameras; ++k) {
    if (c->working.cameras[k].has_intrinsics) continue;
    if (c->options.method != Method::kJoint)
      throw InputError("", "/cameras/" + std::to_string(k) + "/intrinsics",
                       "intrinsics for camera '" + c->dataset.cameras[k].name +
                           "': only --method joint estimates them from the views");
    const internal::EstimatedIntrinsics estimate =
        internal::EstimateIntrinsics(c->working, static_cast<int>(k));
    c->working.cameras[k] = estimate.camera;
    c->estimated[k] = true;
    const Camera& camera = c->working.cameras[k];
    std::ostringstream note;
    note.precision(5);
    note << "camera '" << c->dataset.cameras[k].name
         << "' has no intrinsics: started from fx, fy, cx, cy = " << camera.fx() << ", "
         << camera.fy() << ", " << camera.cx() << ", " << camera.cy()
         << " estimated from its views, refined in the joint solve";
    if (!estimate.weakly.empty())
      note << " (its views alone determine them only weakly, " << estimate.weakly
           << ": the robot's motions must, which the solve's σ of them then shows)";
    c->result.notes.push_back(note.str());
  }
  c->start_cameras = c->working.cameras;
  for (const auto& [name, T_cam] : c->options.fixed_cameras)
    if (c->dataset.CameraIndex(name) < 0)
      throw InputError("", "/cameras", "a camera named '" + name + "' to hold at its given pose");
}

/// Stage 2: the views (PnP each), the setup checks, the robot-motion vote;
/// too few usable views or too little motion end the calibration here.
void PrepareViews(Calibration* c) {
  c->problem = internal::BuildProblem(c->working, c->options);
  Problem& problem = c->problem;
  if (c->options.check_setup) {
    internal::LeaveOutRepeatedViews(&problem);
    c->result.notes.push_back(internal::CheckSetupMistakes(problem, c->options.threads));
  } else {
    c->result.notes.push_back(
        "the setup checks were skipped: the data were taken as they are (--accept-setup)");
  }
  if (c->options.reject_views) {
    internal::RejectInconsistentMotions(&problem);
    if (const std::string flipped = FlippedViewsNote(problem); !flipped.empty())
      c->result.notes.push_back(flipped);
  }
  if (c->options.method == Method::kJoint)
    for (const std::string& note : CameraNoiseNotes(problem)) c->result.notes.push_back(note);
  int used_views = 0;
  for (const View& view : problem.views) used_views += view.used ? 1 : 0;
  if (used_views < 3)
    throw SolveError("too few views: " + std::to_string(used_views) +
                     " usable views of the target" + NoPlanePoseHint(problem, -1) +
                     "; take at least 3 (better 10 or more) robot poses with the target in view");
  internal::CheckMotionDiversity(problem);
}

/// Stage 4: what the solution says of the views and the robot records, the
/// solver's convergence, and the pairs of the methods without pair parameters
/// (chained through the base).
void ExplainViews(Calibration* c) {
  CalibrationResult& result = c->result;
  if (!result.solver.converged) {
    std::ostringstream warning;
    warning.precision(3);
    warning << "the solver stopped at the iteration limit (" << c->options.max_iterations
            << " iterations) while the estimate was still moving by more than "
            << c->options.step_tolerance_mm << " mm / " << c->options.step_tolerance_deg
            << " deg per iteration; the result is written but may not be final";
    result.warnings.push_back(GeneralWarning(WarningKind::kNotConverged, warning.str()));
  }
  const internal::TargetPoses T_holder_target = c->est.Targets();
  internal::ExplainInconsistentViews(&c->problem, c->est.T_cam_mount, T_holder_target);
  ViewsLeftOutWarnings(c->problem, &result.warnings);
  const auto pose_warnings =
      internal::PoseRecordWarnings(c->problem, c->est.T_cam_mount, T_holder_target);
  result.warnings.insert(result.warnings.end(), pose_warnings.begin(), pose_warnings.end());
  if (!result.camera_pairs.empty() || c->options.method == Method::kJoint) return;
  const auto& T_cam_mount = c->est.T_cam_mount;
  for (size_t k = 0; k < T_cam_mount.size(); ++k)
    for (size_t t = k + 1; t < T_cam_mount.size(); ++t) {
      if (!T_cam_mount[k] || !T_cam_mount[t]) continue;
      CameraPairResult p;
      p.camera_k = c->dataset.cameras[k].name;
      p.camera_t = c->dataset.cameras[t].name;
      p.T_camk_camt = *T_cam_mount[k] * T_cam_mount[t]->inverse();
      result.camera_pairs.push_back(p);
    }
}

/// Stage 5: the result's views and cameras, with what the strategy found of
/// each camera (refined intrinsics, leave-one-pose-out figures).
void FillResultStage(Calibration* c) {
  FillResult(c->problem, c->est, &c->result);
  for (auto& [k, intrinsics] : c->refined_intrinsics) c->result.cameras[k].intrinsics = intrinsics;
  for (size_t k = 0; k < c->camera_validation.size(); ++k)
    if (c->camera_validation[k].folds > 0)
      c->result.cameras[k].cross_validation = c->camera_validation[k];
}

/// Stage 6: do the views agree with the focal length and principal point
/// not refined (CalibrationOptions::check_intrinsics)? Then each camera's σ.
/// Intrinsics the views find off bias the camera, which no covariance of the
/// solve with them held holds: its σ takes the shift as a term of its own,
/// the one the views alone give (not drawn to the given values by the prior,
/// as the solve's is). Where the camera's views fit its model (CameraResult::rms_px,
/// which DiagnoseSolution filled, within QualityThresholds::max_camera_rms_px), the shift is an
/// offset of the given fx, fy, cx, cy that new views through them share: it joins the part the
/// given intrinsics add, which `check` leaves out. Where they do not, the check has read a misfit
/// of the model as such a shift, which new views need not share: it counts as the views' own.
/// Unmoved cameras moved, in units of the check's σ (bench/leave-out, mm / deg), on rendered cells
/// with given intrinsics 1 % / 3 px off 1.10 / 0.95 left out and 0.15 / 0.57
/// kept in; on METRIC as published (principal points off) 1.01 / 0.97 and
/// 0.36 / 0.27; on industrial_calibration's ChArUco set (no distortion model,
/// residuals 1.96 px) 1.76 / 1.49 with a false alarm in 8 splits left out,
/// 1.03 / 1.10 kept in. Each robot pose is a block under the robot error the
/// cameras' σ carries (Calibration::covariance_robot): where the poses were
/// taken as exact though the views showed that error, a check with them
/// exact had called true intrinsics off (bench/leave-out's rendered ChArUco
/// cell, robot 0.1 mm, seed 3: 6 of 32 quarters of the poses left out
/// warned, 5 of them among the 8 that took the exact robot; 3 with the
/// pose blocks).
void IntrinsicsCheckAndSigma(Calibration* c) {
  internal::CameraCovariance& camera_covariance = c->camera_covariance;
  if (c->options.check_intrinsics) {
    std::map<size_t, internal::IntrinsicsOff> off;
    const auto intrinsics_warnings = internal::IntrinsicsWarnings(
        c->problem, c->est.T_cam_mount, c->est.Targets(),
        std::max(1.0, c->result.solver.cauchy_scale_px),
        internal::UnrefinedIntrinsics(c->free_intrinsics, c->dataset.cameras.size()),
        c->covariance_robot, &off);
    c->result.warnings.insert(c->result.warnings.end(), intrinsics_warnings.begin(),
                              intrinsics_warnings.end());
    for (const auto& [k, found] : off)
      if (camera_covariance.covariance.count(k)) {
        const bool model_fits = c->result.cameras[k].rms_px <= c->options.warn.max_camera_rms_px;
        (model_fits ? camera_covariance.from_intrinsics : camera_covariance.covariance)[k] +=
            found.moved * found.moved.transpose();
        // The groups it names: their shift is the views' alone (found.moved);
        // the others keep what the views and the prior say of them.
        const auto own = camera_covariance.own_intrinsics_shift.find(k);
        const auto shift = camera_covariance.intrinsics_shift.find(k);
        Eigen::Vector4d offset = found.offset_px;
        if (own == camera_covariance.own_intrinsics_shift.end() ||
            shift == camera_covariance.intrinsics_shift.end()) {
          camera_covariance.intrinsics_shift.erase(k);
        } else {
          const auto suggested = camera_covariance.intrinsics_offset.find(k);
          for (int j = 0; j < 4; ++j) {
            if (found.Groups() & (j < 2 ? kFocal : kPrincipalPoint))
              shift->second -= own->second.col(j);
            else if (suggested != camera_covariance.intrinsics_offset.end())
              offset[j] = suggested->second[j];
          }
        }
        camera_covariance.intrinsics_offset[k] = offset;
      }
  }
  for (const auto& [k, moved] : camera_covariance.intrinsics_shift)
    if (camera_covariance.covariance.count(k))
      camera_covariance.from_intrinsics[k] += moved * moved.transpose();
  for (const auto& [k, covariance] : camera_covariance.covariance) {
    const Eigen::Matrix<double, 6, 6>& from_intrinsics = camera_covariance.from_intrinsics[k];
    PoseUncertainty sigma =
        internal::UncertaintyOf(*c->est.T_cam_mount[k], covariance + from_intrinsics, true);
    sigma.from_given_intrinsics =
        internal::UncertaintyOf(*c->est.T_cam_mount[k], from_intrinsics, true).covariance;
    if (const auto cross = camera_covariance.with_target.find(k);
        cross != camera_covariance.with_target.end() && !c->est.per_camera_target)
      sigma.covariance_with_target =
          internal::UncertaintyJacobian(*c->est.T_cam_mount[k], true) * cross->second *
          internal::UncertaintyJacobian(c->est.shared_T_holder_target, false).transpose();
    c->result.cameras[k].sigma = sigma;
    if (const auto offset = camera_covariance.intrinsics_offset.find(k);
        offset != camera_covariance.intrinsics_offset.end())
      c->result.cameras[k].given_intrinsics_offset_px = offset->second;
  }
}

}  // namespace internal

CalibrationResult Calibrate(const Dataset& dataset, const CalibrationOptions& options) {
  std::string why;
  if (!options.Check(&why)) throw InputError("", "", "invalid calibration options: " + why);
  const auto start = std::chrono::steady_clock::now();
  Calibration c(dataset, options);
  c.result.setup = dataset.setup;
  c.result.method = options.method;
  internal::PrepareCameras(&c);
  internal::PrepareViews(&c);
  if (options.method == Method::kJoint)
    internal::SolveJointMethod(&c);
  else if (options.method == Method::kPerCamera)
    internal::SolvePerCameraMethod(&c);
  else
    internal::SolveClosedFormMethod(&c);
  internal::ExplainViews(&c);
  internal::FillResultStage(&c);
  // The residuals first (the intrinsics stage reads each camera's RMS); the
  // intrinsics warnings still come before the quality warnings.
  const auto quality =
      internal::DiagnoseSolution(c.problem, c.est.T_cam_mount, c.est.Targets(), options, &c.result);
  internal::IntrinsicsCheckAndSigma(&c);
  c.result.warnings.insert(c.result.warnings.end(), quality.begin(), quality.end());
  c.result.options = options;
  c.result.handeye_version = HANDEYE_VERSION;
  c.result.solver.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return std::move(c.result);
}

}  // namespace handeye
