// SPDX-License-Identifier: GPL-2.0-or-later
// Calibrate(): picks the method, runs initialisation and refinement, and
// fills the result with per-view residuals and the paper's metrics.
#include <algorithm>
#include <chrono>
#include <functional>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "calibration_internal.h"
#include "diagnostics_internal.h"
#include "setup_mistakes.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"

namespace handeye {
namespace {

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

// The estimate: each camera's T_cam_mount and the T_holder_target it uses.
struct Estimate {
  std::vector<std::optional<Eigen::Isometry3d>> T_cam_mount;
  std::vector<Eigen::Isometry3d> T_holder_target;  // per camera
  Eigen::Isometry3d shared_T_holder_target = Eigen::Isometry3d::Identity();
  bool per_camera_target = false;
};

// One camera's closed-form (T_cam_mount, T_holder_target), or nullopt with the reason.
using CameraSolve = std::function<std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>>(
    int camera, std::string* why)>;

// Per-camera methods: a closed form (`solve`, named `method_name` in
// warnings) on every camera that has the views for it; the others are
// reported, not fatal.
Estimate PerCameraEstimate(const Problem& problem, const CameraSolve& solve, const std::string& method_name,
                           std::vector<Warning>* warnings) {
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
      warnings->push_back(CameraWarning(WarningKind::kCameraMethodFailed, problem.dataset->cameras[k].name,
                                        "camera '" + problem.dataset->cameras[k].name + "' not calibrated by " +
                                            method_name + ": " + why));
      continue;
    }
    est.T_cam_mount[k] = solved->first;
    est.T_holder_target[k] = solved->second;
    solved_T_holder_target.push_back(solved->second);
  }
  if (solved_T_holder_target.empty())
    throw SolveError("method '" + method_name + "' could not calibrate any camera (see warnings)");
  est.shared_T_holder_target = internal::MeanTransform(solved_T_holder_target);
  return est;
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
      result->warnings.push_back(CameraWarning(WarningKind::kCameraNotSeen, cam.name,
                                               "camera '" + cam.name + "' never saw the target: not calibrated"));
    } else if (cam.views == 0) {
      result->warnings.push_back(CameraWarning(
          WarningKind::kCameraNoUsableViews, cam.name,
          "camera '" + cam.name + "': the target was detected in " +
          std::to_string(cam.views_rejected) + " views, but none was usable" +
          NoPlanePoseHint(problem, static_cast<int>(k)) + ": not calibrated"));
    }
    result->cameras.push_back(cam);
  }
  result->T_target = est.shared_T_holder_target;
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
         " of the 180°-ambiguous board were numbered half a turn round from the others (no detector "
         "can tell); the robot's motions say so, and they were used with their ids reversed "
         "(id -> N - 1 - id; `flipped` in the views); pose/camera: " + list;
}

/// For each camera, the groups the intrinsics check looks at: focal length
/// and principal point, less those the joint solve refines (parameter
/// indices in `free_intrinsics`: 0 fx, 2 cx).
std::vector<unsigned> UnrefinedIntrinsics(const std::vector<std::vector<int>>& free_intrinsics, size_t num_cameras) {
  std::vector<unsigned> check(num_cameras, kFocal | kPrincipalPoint);
  for (size_t k = 0; k < free_intrinsics.size() && k < num_cameras; ++k)
    for (int p : free_intrinsics[k]) {
      if (p == 0) check[k] &= ~unsigned(kFocal);
      if (p == 2) check[k] &= ~unsigned(kPrincipalPoint);
    }
  return check;
}

/// The per-camera reprojection solve from `est` (each camera with its own
/// T_holder_target over all its views), made robust (RobustSolve); `est`
/// ends at the solution.
internal::Refinement SolvePerCamera(Problem* problem, const CalibrationOptions& options, Estimate* est,
                                    std::vector<Warning>* warnings) {
  const double first_scale =
      std::max(1.0, 3.0 * internal::ResidualSigmaPx(*problem, est->T_cam_mount, est->T_holder_target));
  const internal::Refinement refined = internal::RobustSolve(
      problem, options, first_scale,
      [&](double scale) {
        CalibrationOptions round = options;
        round.cauchy_scale_px = scale;
        internal::Refinement r = internal::RefinePerCamera(*problem, est->T_cam_mount, est->T_holder_target, round);
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

/// Per camera (tangent of T_cam_mount): the covariance, and where the held
/// given intrinsics at what the views and their prior say would move it
/// (Refinement::T_cam_mount_intrinsics_shift).
/// `from_intrinsics`: the part of `covariance` their uncertainty adds.
struct CameraCovariance {
  std::map<size_t, Eigen::Matrix<double, 6, 6>> covariance, from_intrinsics;
  std::map<size_t, Eigen::Matrix<double, 6, 1>> intrinsics_shift;
  void Add(const internal::Refinement& computed, size_t k) {
    if (!computed.T_cam_mount_covariance[k]) return;
    covariance[k] = *computed.T_cam_mount_covariance[k];
    from_intrinsics[k] = computed.T_cam_mount_intrinsics_covariance[k].value_or(Eigen::Matrix<double, 6, 6>::Zero());
    if (computed.T_cam_mount_intrinsics_shift[k]) intrinsics_shift[k] = *computed.T_cam_mount_intrinsics_shift[k];
  }
};

/// Each camera's covariance under the per-camera model at `est` (its
/// solution, solved with loss scale `cauchy_scale_px`).
CameraCovariance PerCameraCovariance(const Problem& problem, const Estimate& est, const CalibrationOptions& options,
                                     double cauchy_scale_px) {
  CalibrationOptions at = options;
  at.cauchy_scale_px = cauchy_scale_px;
  const internal::Refinement covariance = internal::RefinePerCamera(problem, est.T_cam_mount, est.T_holder_target, at,
                                                                    internal::JointStep::kCovariance);
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
    const internal::Refinement refined = SolvePerCamera(&copy, options, &solved, &ignored);
    out = PerCameraCovariance(copy, solved, options, refined.summary.cauchy_scale_px);
  } catch (const SolveError&) {
    return out;  // no solve to measure it by: no σ
  }
  const internal::PoseManifold manifold;
  for (auto& [k, covariance] : out.covariance) {
    const PoseParams at = ToPoseParams(*solved.T_cam_mount[k]), cf = ToPoseParams(*closed_form.T_cam_mount[k]);
    Eigen::Matrix<double, 6, 1> d;
    manifold.Minus(cf.data(), at.data(), d.data());
    covariance += d * d.transpose();
  }
  return out;
}

}  // namespace

CalibrationResult Calibrate(const Dataset& dataset, const CalibrationOptions& options) {
  std::string why;
  if (!options.Check(&why)) throw InputError("", "", "invalid calibration options: " + why);
  const auto start = std::chrono::steady_clock::now();
  CalibrationResult result;
  result.setup = dataset.setup;
  result.method = options.method;

  // The cameras as the solver sees them: intrinsics estimated where the
  // dataset gives none, and refined by the joint solve where asked.
  Dataset working = dataset;
  const size_t num_cameras = dataset.cameras.size();
  std::vector<bool> estimated(num_cameras, false);
  for (size_t k = 0; k < num_cameras; ++k) {
    if (working.cameras[k].has_intrinsics) continue;
    if (options.method != Method::kJoint)
      throw InputError("", "/cameras/" + std::to_string(k) + "/intrinsics",
                       "intrinsics for camera '" + dataset.cameras[k].name +
                           "': only --method joint estimates them from the views");
    working.cameras[k] = internal::EstimateIntrinsics(working, static_cast<int>(k));
    estimated[k] = true;
    std::ostringstream note;
    note.precision(5);
    note << "camera '" << dataset.cameras[k].name << "' has no intrinsics: started from fx, fy, cx, cy = "
         << working.cameras[k].fx() << ", " << working.cameras[k].fy() << ", " << working.cameras[k].cx() << ", "
         << working.cameras[k].cy() << " estimated from its views, refined in the joint solve";
    result.notes.push_back(note.str());
  }
  const std::vector<Camera> start_cameras = working.cameras;
  for (const auto& [name, T_cam] : options.fixed_cameras)
    if (dataset.CameraIndex(name) < 0)
      throw InputError("", "/cameras", "a camera named '" + name + "' to hold at its given pose");

  Problem problem = internal::BuildProblem(working, options);
  if (options.check_setup) {
    internal::LeaveOutRepeatedViews(&problem);
    result.notes.push_back(internal::CheckSetupMistakes(problem));
  } else {
    result.notes.push_back("the setup checks were skipped: the data were taken as they are (--accept-setup)");
  }
  if (options.reject_views) {
    internal::RejectInconsistentMotions(&problem);
    if (const std::string flipped = FlippedViewsNote(problem); !flipped.empty())
      result.notes.push_back(flipped);
  }
  int used_views = 0;
  for (const View& view : problem.views) used_views += view.used ? 1 : 0;
  if (used_views < 3)
    throw SolveError("too few views: " + std::to_string(used_views) +
                     " usable views of the target" + NoPlanePoseHint(problem, -1) +
                     "; take at least 3 (better 10 or more) robot poses with the target in view");
  internal::CheckMotionDiversity(problem);

  Estimate est;
  std::vector<std::vector<int>> undetermined(num_cameras);
  std::map<size_t, IntrinsicsResult> refined_intrinsics;
  std::optional<internal::RobotPrior> robot_model;  // the joint solve's, when it modelled the robot's error
  std::vector<std::vector<int>> free_intrinsics;      // the joint solve's, by camera
  CameraCovariance camera_covariance;
  std::vector<CameraResult::CrossValidation> camera_validation;
  if (options.method == Method::kJoint) {
    internal::Initialisation init = internal::InitialiseJoint(problem);
    result.notes.insert(result.notes.end(), init.notes.begin(), init.notes.end());
    init.fixed_T_cam_mount.assign(num_cameras, false);
    for (const auto& [name, T_cam] : options.fixed_cameras) {
      const int k = dataset.CameraIndex(name);
      if (!init.T_cam_mount[k]) continue;  // no views: nothing to hold
      init.T_cam_mount[k] = T_cam.inverse();
      init.fixed_T_cam_mount[k] = true;
    }
    if (!options.fixed_cameras.empty()) {
      // The target transform from the held cameras' views, so the others start consistent.
      std::vector<Eigen::Isometry3d> T_holder_target_estimates;
      for (size_t k = 0; k < num_cameras; ++k)
        if (init.fixed_T_cam_mount[k])
          if (const auto T_holder_target =
                  internal::TargetGivenCamera(problem, static_cast<int>(k), *init.T_cam_mount[k]))
            T_holder_target_estimates.push_back(*T_holder_target);
      if (!T_holder_target_estimates.empty()) {
        init.T_holder_target = internal::MeanTransform(T_holder_target_estimates);
        for (size_t k = 0; k < num_cameras; ++k)
          if (init.T_cam_mount[k] && !init.fixed_T_cam_mount[k])
            if (const auto T_cam_mount =
                    internal::CameraGivenTarget(problem, static_cast<int>(k), init.T_holder_target))
              init.T_cam_mount[k] = *T_cam_mount;
        result.notes.push_back(std::to_string(options.fixed_cameras.size()) +
                               " camera(s) held at their given poses; the others and the target transform solved");
      }
    }
    init.free_intrinsics.resize(num_cameras);
    for (size_t k = 0; k < num_cameras; ++k) {
      const unsigned groups = estimated[k] ? kAllIntrinsics : options.refine_intrinsics;
      if (groups & kDistortion && working.cameras[k].num_distortion == 0) working.cameras[k].num_distortion = 5;
      init.free_intrinsics[k] = internal::FreeIntrinsics(working.cameras[k], groups);
    }
    free_intrinsics = init.free_intrinsics;
    init.given_cameras = start_cameras;
    init.pixel_sigma_px = internal::DetectionSigmaPx(problem);
    // One joint solve (with the intrinsics under their prior), then PnP again
    // with the refined intrinsics.
    auto refine = [&](const CalibrationOptions& round, const std::optional<internal::RobotPrior>& robot) {
      internal::Refinement r = internal::RefineJoint(problem, init, round, robot);
      bool changed = false;
      for (size_t k = 0; k < num_cameras; ++k) {
        changed = changed || working.cameras[k].params != r.intrinsics[k];
        working.cameras[k].params = r.intrinsics[k];
      }
      // PnP with the new intrinsics: the robot error estimate compares with it.
      if (changed) internal::RecomputePnp(&problem, options.pnp_max_rms_px);
      return r;
    };
    // The first loss scale from the residuals at the closed-form start: a
    // start that is far off is then solved nearly as least squares, and the
    // scale narrows once the residuals are known.
    const double first_scale = std::max(
        1.0, 3.0 * internal::ResidualSigmaPx(problem, init.T_cam_mount,
                                             internal::TargetPoses(dataset.cameras.size(), init.T_holder_target)));
    std::optional<internal::RobotPrior> robot;
    bool solved_once = false;
    const internal::Refinement refined = internal::RobustSolve(
        &problem, options, first_scale,
        [&](double scale) {
          CalibrationOptions round = options;
          round.cauchy_scale_px = scale;
          // The robot's pose error: as given, or estimated from the last
          // solution (the first round solves with exact poses first).
          if (options.robot_sigma_mm > 0) {
            robot = internal::RobotPrior{options.robot_sigma_mm / 1000.0, options.robot_sigma_deg * M_PI / 180.0,
                                         internal::DetectionSigmaPx(problem)};
          } else if (options.robot_sigma_mm < 0) {
            if (!solved_once) {
              internal::WarmStart(refine(round, std::nullopt), &init);
              solved_once = true;
            }
            const internal::TargetPoses T_holder_target_now(dataset.cameras.size(), init.T_holder_target);
            robot = internal::EstimateRobotPrior(problem, init.T_cam_mount, T_holder_target_now);
            // Intrinsics that do not fit raise the chain's residuals too, and
            // pose blocks would absorb that misfit (METRIC as published: its
            // principal points are 1–3 px off). Where the views say the given
            // focal length or principal point is off even with the robot's
            // error modelled, only a clear excess (2× PnP's) counts as the robot's.
            if (robot && robot->chain_to_pnp < 2.0 &&
                !internal::IntrinsicsWarnings(problem, init.T_cam_mount, T_holder_target_now, scale,
                                              UnrefinedIntrinsics(init.free_intrinsics, num_cameras), robot)
                     .empty())
              robot.reset();
          }
          internal::Refinement r = refine(round, robot);
          internal::WarmStart(r, &init);  // of the next round
          return r;
        },
        &result.warnings);
    // How large the robot's error is, as the solved pose blocks show it: the
    // rule that estimated the prior errs wide on purpose (on rendered cells
    // it made σ about twice the error).
    if (robot && options.robot_sigma_mm < 0) {
      CalibrationOptions round = options;
      round.cauchy_scale_px = refined.summary.cauchy_scale_px;
      internal::SettleRobotSigma(problem, init, refined, round, &*robot);
    }
    if (robot && options.robot_sigma_mm < 0 && options.check_setup) internal::CheckRobotSigma(*robot);
    robot_model = robot;
    if (robot) {
      result.solver.robot_sigma_mm = robot->sigma_m * 1000.0;
      result.solver.robot_sigma_deg = robot->sigma_rad * 180.0 / M_PI;
      std::ostringstream note;
      note.precision(3);
      note << "the robot's own pose error is modelled (one pose block per robot pose): σ " << robot->sigma_m * 1000.0
           << " mm and " << robot->sigma_rad * 180.0 / M_PI << " deg per axis"
           << (options.robot_sigma_mm > 0 ? " (given)" : " (estimated from the views)") << ", detection σ "
           << robot->pixel_sigma_px << " px";
      if (robot->settled_sigma_m > 0)
        note << "; the solved poses show σ " << robot->settled_sigma_m * 1000.0 << " mm and "
             << robot->settled_sigma_rad * 180.0 / M_PI << " deg, which the cameras' sigma assumes";
      result.notes.push_back(note.str());
    }
    est.T_cam_mount = refined.T_cam_mount;
    est.shared_T_holder_target = refined.T_holder_target[0];
    // How well the solution is known: the same problem at the solution.
    CalibrationOptions final_options = options;
    final_options.cauchy_scale_px = refined.summary.cauchy_scale_px;
    const internal::Refinement covariance =
        internal::RefineJoint(problem, init, final_options, robot, internal::JointStep::kCovariance);
    if (options.cross_validate) internal::CrossValidate(problem, init, final_options, robot, &camera_validation);
    for (size_t k = 0; k < num_cameras; ++k)
      if (est.T_cam_mount[k] && covariance.T_cam_mount_covariance[k])
        camera_covariance.Add(covariance, k);
    if (covariance.T_holder_target_covariance)
      result.target_sigma =
          internal::UncertaintyOf(est.shared_T_holder_target, *covariance.T_holder_target_covariance, false);
    for (size_t k = 0; k < num_cameras; ++k) {
      if (init.free_intrinsics[k].empty() || !est.T_cam_mount[k]) continue;  // no views: nothing refined
      for (int p : internal::UndeterminedIntrinsics(start_cameras[k], covariance.intrinsics_sigma[k],
                                                    init.free_intrinsics[k])) {
        if (estimated[k] && p < 4)
          throw SolveError("camera '" + dataset.cameras[k].name +
                           "' has no intrinsics and the views do not determine its " + Camera::ParamName(p) +
                           "; take views with the target tilted by 20° or more in different directions and "
                           "covering the image, or give the camera's intrinsics in the dataset");
        undetermined[k].push_back(p);
      }
      IntrinsicsResult intrinsics;
      intrinsics.camera = working.cameras[k];
      intrinsics.camera.has_intrinsics = true;
      intrinsics.sigma = covariance.intrinsics_sigma[k];
      for (int p : init.free_intrinsics[k]) intrinsics.refined.push_back(Camera::ParamName(p));
      for (int p : undetermined[k]) intrinsics.undetermined.push_back(Camera::ParamName(p));
      if (!undetermined[k].empty()) {
        std::string names;
        for (const auto& name : intrinsics.undetermined) names += (names.empty() ? "" : ", ") + name;
        result.warnings.push_back(CameraWarning(WarningKind::kIntrinsicsUndetermined, dataset.cameras[k].name,
                                  "camera '" + dataset.cameras[k].name + "': the views hardly determine " + names +
                                  ", which a prior keeps near the " +
                                  (estimated[k] ? "estimate from the views alone" : "given values") +
                                  " (1σ: an image corner within 20 px); see intrinsics_sigma"));
      }
      refined_intrinsics[k] = intrinsics;
    }
    const double robot_mm = result.solver.robot_sigma_mm, robot_deg = result.solver.robot_sigma_deg;
    result.solver = refined.summary;
    result.solver.robot_sigma_mm = robot_mm;
    result.solver.robot_sigma_deg = robot_deg;
    // Poses at which each camera has a used view, to count shared views per pair.
    std::vector<std::set<int>> poses_seen(dataset.cameras.size());
    for (const View& view : problem.views)
      if (view.used) poses_seen[view.camera].insert(view.pose);
    for (const auto& [pair, T_kt] : refined.pairs) {
      if (pair.first > pair.second) continue;  // report each unordered pair once, k < t
      CameraPairResult p;
      p.camera_k = dataset.cameras[pair.first].name;
      p.camera_t = dataset.cameras[pair.second].name;
      p.T_camk_camt = T_kt;
      for (int pose : poses_seen[pair.first]) p.shared_views += poses_seen[pair.second].count(pose) ? 1 : 0;
      result.camera_pairs.push_back(p);
    }
  } else if (options.method == Method::kPerCamera) {
    // Each camera on its own: a closed form that prints nothing (on diverse
    // views) then the reprojection solve with its own T_holder_target over all views.
    const Problem diverse = internal::WithDiverseViews(problem, 12);
    est = PerCameraEstimate(
        diverse,
        [&](int camera, std::string* why) {
          std::string chosen;
          return internal::SilentClosedFormHandEye(diverse, camera, &chosen, why);
        },
        MethodName(options.method), &result.warnings);
    const internal::Refinement refined = SolvePerCamera(&problem, options, &est, &result.warnings);
    std::vector<Eigen::Isometry3d> solved;
    for (size_t k = 0; k < est.T_cam_mount.size(); ++k)
      if (est.T_cam_mount[k]) solved.push_back(est.T_holder_target[k]);
    est.shared_T_holder_target = internal::MeanTransform(solved);
    result.solver = refined.summary;
    camera_covariance = PerCameraCovariance(problem, est, options, refined.summary.cauchy_scale_px);
  } else {
    est = PerCameraEstimate(
        problem,
        [&](int camera, std::string* why) {
          return internal::ClosedFormHandEye(problem, camera, options.method, why);
        },
        MethodName(options.method), &result.warnings);
    result.solver.converged = true;
    result.solver.termination = "CLOSED_FORM";
    camera_covariance = ClosedFormCovariance(problem, est, options);
  }
  if (!result.solver.converged) {
    std::ostringstream warning;
    warning.precision(3);
    warning << "the solver stopped at the iteration limit (" << options.max_iterations
            << " iterations) while the estimate was still moving by more than "
            << options.step_tolerance_mm << " mm / " << options.step_tolerance_deg
            << " deg per iteration; the result is written but may not be final";
    result.warnings.push_back(GeneralWarning(WarningKind::kNotConverged, warning.str()));
  }
  internal::TargetPoses T_holder_target(dataset.cameras.size(), est.shared_T_holder_target);
  if (est.per_camera_target) T_holder_target = est.T_holder_target;
  internal::ExplainInconsistentViews(&problem, est.T_cam_mount, T_holder_target);
  // Views seen too obliquely are common on a camera network (boards turned
  // away from a camera): one warning names them all.
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
    Warning left_out = CameraWarning(WarningKind::kViewLeftOut, view.observation->camera,
                                     "view of pose '" + view.observation->pose_id + "' by camera '" +
                                         view.observation->camera + "' left out: " + view.rejected_because);
    left_out.pose = view.observation->pose_id;
    left_out.view = static_cast<int>(i);  // FillResult lists the views in the problem's order
    result.warnings.push_back(std::move(left_out));
  }
  if (num_oblique)
    result.warnings.push_back(GeneralWarning(
        WarningKind::kObliqueViewsLeftOut,
        std::to_string(num_oblique) + " view" + (num_oblique > 1 ? "s" : "") +
        " left out, the target seen more than " +
        std::to_string(std::lround(internal::kMaxViewAngleDeg)) +
        " deg from face-on (too squeezed for a good pose); pose/camera (deg): " + oblique.str()));
  const auto pose_warnings = internal::PoseRecordWarnings(problem, est.T_cam_mount, T_holder_target);
  result.warnings.insert(result.warnings.end(), pose_warnings.begin(), pose_warnings.end());
  // Pairs for the methods without pair parameters: chained through the base.
  if (result.camera_pairs.empty() && options.method != Method::kJoint) {
    for (size_t k = 0; k < est.T_cam_mount.size(); ++k)
      for (size_t t = k + 1; t < est.T_cam_mount.size(); ++t) {
        if (!est.T_cam_mount[k] || !est.T_cam_mount[t]) continue;
        CameraPairResult p;
        p.camera_k = dataset.cameras[k].name;
        p.camera_t = dataset.cameras[t].name;
        p.T_camk_camt = *est.T_cam_mount[k] * est.T_cam_mount[t]->inverse();
        result.camera_pairs.push_back(p);
      }
  }
  FillResult(problem, est, &result);
  for (auto& [k, intrinsics] : refined_intrinsics) result.cameras[k].intrinsics = intrinsics;
  for (size_t k = 0; k < camera_validation.size(); ++k)
    if (camera_validation[k].folds > 0) result.cameras[k].cross_validation = camera_validation[k];
  if (options.check_intrinsics) {
    // Focal length and principal point not refined: do the views agree with them?
    std::map<size_t, Eigen::Matrix<double, 6, 1>> shift;
    const auto intrinsics_warnings = internal::IntrinsicsWarnings(
        problem, est.T_cam_mount, T_holder_target, std::max(1.0, result.solver.cauchy_scale_px),
        UnrefinedIntrinsics(free_intrinsics, num_cameras), robot_model, &shift);
    result.warnings.insert(result.warnings.end(), intrinsics_warnings.begin(), intrinsics_warnings.end());
    // Intrinsics the views find off bias the camera, which no covariance of
    // the solve with them held holds: its σ takes the shift as a term of its
    // own, the one the views alone give (not drawn to the given values by
    // the prior, as the solve's is).
    // (That shift was in σ before the given intrinsics were uncertain
    // inputs, so it is not counted in the part they add.)
    for (const auto& [k, moved] : shift)
      if (camera_covariance.covariance.count(k)) {
        camera_covariance.covariance[k] += moved * moved.transpose();
        camera_covariance.intrinsics_shift.erase(k);
      }
  }
  for (const auto& [k, moved] : camera_covariance.intrinsics_shift)
    if (camera_covariance.covariance.count(k)) camera_covariance.from_intrinsics[k] += moved * moved.transpose();
  for (const auto& [k, covariance] : camera_covariance.covariance) {
    const Eigen::Matrix<double, 6, 6>& from_intrinsics = camera_covariance.from_intrinsics[k];
    PoseUncertainty sigma = internal::UncertaintyOf(*est.T_cam_mount[k], covariance + from_intrinsics, true);
    sigma.from_given_intrinsics = internal::UncertaintyOf(*est.T_cam_mount[k], from_intrinsics, true).covariance;
    result.cameras[k].sigma = sigma;
  }
  const auto quality = internal::DiagnoseSolution(problem, est.T_cam_mount, T_holder_target, options, &result);
  result.warnings.insert(result.warnings.end(), quality.begin(), quality.end());
  result.options = options;
  result.handeye_version = HANDEYE_VERSION;
  result.solver.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace handeye
