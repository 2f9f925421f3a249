// SPDX-License-Identifier: GPL-2.0-or-later
// The diagnostics of a solution, computed once: residuals per view and per
// camera, AX = ZB, robot motion diversity, the closed-form comparison, and the
// warnings a person must see before accepting a calibration. Calibrate() runs
// them on its own problem; Diagnose() on a result changed or read from a file.
// The closed-form comparison itself: closed_form_comparison.cc.
#include "handeye/core/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "closed_form.h"
#include "diagnostics_internal.h"
#include "half_turn.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "parallel.h"
#include "problem.h"
#include "residuals.h"

namespace handeye::internal {

std::string Fixed(double value, int decimals) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(decimals);
  out << value;
  return out.str();
}

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// The closed form a result is compared with: Park & Martin, or Tsai & Lenz
// for a result that is Park's own (both OpenCV's; ViSP would print).
Method ComparisonMethod(Method method) {
  return method == Method::kPark ? Method::kTsai : Method::kPark;
}

std::vector<Warning> QualityWarnings(
    const Problem& problem, const CalibrationOptions& options, const CalibrationResult& result,
    const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target) {
  const QualityThresholds& warn = options.warn;
  std::vector<Warning> warnings;
  for (size_t k = 0; k < result.cameras.size(); ++k) {
    const CameraResult& cam = result.cameras[k];
    if (!cam.calibrated) continue;  // warned about where it was left out
    const std::string name = "camera '" + cam.name + "'";
    if (cam.views < warn.min_views_per_camera)
      warnings.push_back(CameraWarning(
          WarningKind::kFewViews, cam.name,
          name + ": few views, only " + std::to_string(cam.views) + " used (fewer than " +
              std::to_string(warn.min_views_per_camera) +
              "); one bad pose moves its result visibly; add robot poses in its view"));
    if (cam.rotation_spread_deg < warn.min_rotation_spread_deg)
      warnings.push_back(CameraWarning(
          WarningKind::kPoorRotationSpread, cam.name,
          name + ": poor rotation diversity, its views differ in robot rotation by at most " +
              Fixed(cam.rotation_spread_deg, 1) + "° (< " + Fixed(warn.min_rotation_spread_deg, 0) +
              "°); tilt the target more between poses"));
    else if (cam.axis_spread_deg < warn.min_axis_spread_deg)
      warnings.push_back(CameraWarning(
          WarningKind::kPoorRotationAxes, cam.name,
          name + ": poor rotation diversity, the robot motions between its views turn about " +
              "nearly one axis (largest angle between axes " + Fixed(cam.axis_spread_deg, 1) +
              "° < " + Fixed(warn.min_axis_spread_deg, 0) + "°); rotate about a second axis too"));
    if (warn.max_camera_rms_px > 0 && cam.rms_px > warn.max_camera_rms_px)
      warnings.push_back(CameraWarning(WarningKind::kLargeResiduals, cam.name,
                                       name + ": large residuals, RMS " + Fixed(cam.rms_px, 2) +
                                           " px through the calibrated chain (> " +
                                           Fixed(warn.max_camera_rms_px, 2) + " px)"));
    if (cam.outliers > 0) {
      std::string list;
      int listed = 0;
      for (size_t i = 0; i < problem.views.size(); ++i) {
        const ViewResult& view = result.views[i];
        if (problem.views[i].camera != static_cast<int>(k) || !view.outlier) continue;
        if (listed++ == 5) {
          list += ", …";
          break;
        }
        list += (list.empty() ? "" : ", ") + std::string("pose ") + view.pose_id + " (RMS " +
                Fixed(view.rms_px, 2) + " px)";
      }
      warnings.push_back(CameraWarning(WarningKind::kOutlierViews, cam.name,
                                       name + ": " + std::to_string(cam.outliers) +
                                           (cam.outliers == 1 ? " view" : " views") +
                                           " down-weighted as outliers by the solver: " + list));
    }
    if (cam.closed_form && cam.closed_form->available && warn.max_closed_form_disagreement_px > 0 &&
        cam.closed_form->displacement_px > warn.max_closed_form_disagreement_px) {
      const std::string cause =
          T_cam_mount[k] ? DisagreementCause(problem, static_cast<int>(k), *T_cam_mount[k],
                                             T_holder_target[k], result.method, *cam.closed_form,
                                             warn.max_closed_form_disagreement_px)
                         : "";
      warnings.push_back(CameraWarning(
          WarningKind::kClosedFormDisagrees, cam.name,
          name + ": the result and " + AuthorName(cam.closed_form->method) +
              "'s per-camera closed form disagree by " +
              Fixed(cam.closed_form->displacement_px, 1) + " px in the image (" +
              Fixed(cam.closed_form->translation_mm, 1) + " mm, " +
              Fixed(cam.closed_form->rotation_deg, 2) + "°; threshold " +
              Fixed(warn.max_closed_form_disagreement_px, 0) + " px); " +
              (cause.empty()
                   ? "the closed forms disagree among themselves too: check this camera's "
                     "robot poses and views"
                   : cause)));
    }
  }
  return warnings;
}

}  // namespace

PoseDifference DifferenceOf(const Eigen::Isometry3d& T_a, const Eigen::Isometry3d& T_b) {
  PoseDifference out;
  out.translation_mm = 1000.0 * (T_a.translation() - T_b.translation()).norm();
  out.rotation_deg = kRadToDeg * RotationDistance(T_a.rotation(), T_b.rotation());
  return out;
}

RobotMotions CollectRobotMotions(const Problem& problem, const std::vector<int>& views) {
  RobotMotions motions;
  for (size_t a = 0; a < views.size(); ++a)
    for (size_t b = a + 1; b < views.size(); ++b) {
      const Eigen::Matrix3d R =
          problem.T_mount_holder[problem.views[views[a]].pose].rotation().transpose() *
          problem.T_mount_holder[problem.views[views[b]].pose].rotation();
      const Eigen::Vector3d rv = RotationVectorFromMatrix(R);
      const double angle = rv.norm();
      motions.largest_deg = std::max(motions.largest_deg, angle * kRadToDeg);
      if (angle * kRadToDeg > kMotionAxisMinDeg) motions.axes.push_back(rv / angle);
    }
  return motions;
}

double AxisSpreadDeg(const std::vector<Eigen::Vector3d>& axes) {
  // Every pair of n² motion axes is n⁴: a few hundred views would take
  // minutes, and an even sample finds the spread as well.
  const size_t step = std::max<size_t>(1, axes.size() / 1500);
  double smallest_cos = 1.0;
  for (size_t a = 0; a < axes.size(); a += step)
    for (size_t b = a + step; b < axes.size(); b += step)
      smallest_cos = std::min(smallest_cos, std::abs(axes[a].dot(axes[b])));
  if (axes.size() < 2) return 0.0;
  return std::acos(std::clamp(smallest_cos, 0.0, 1.0)) * kRadToDeg;
}

AxzbOfView Axzb(const Eigen::Isometry3d& T_cam_target_pnp, const Eigen::Isometry3d& T_cam_mount,
                const Eigen::Isometry3d& T_mount_holder, const Eigen::Isometry3d& T_holder_target) {
  // Paper eq. (real_metrics): A_j X = Z' B_j with A_j = T_target_cam[j] (PnP),
  // X = T_cam_mount, Z' = T_target_holder, B_j = T_holder_mount[j]; both
  // sides are T_target_mount.
  const Eigen::Isometry3d AX = T_cam_target_pnp.inverse() * T_cam_mount;
  const Eigen::Isometry3d ZB = T_holder_target.inverse() * T_mount_holder.inverse();
  // The camera in its mount's frame, from the view and from the solution.
  const Eigen::Isometry3d T_mount_cam_view =
      T_mount_holder * T_holder_target * T_cam_target_pnp.inverse();
  const Eigen::Isometry3d T_mount_cam = T_cam_mount.inverse();
  AxzbOfView out;
  out.target_frame_m = (AX.translation() - ZB.translation()).norm();
  out.camera_frame_m = (T_mount_cam_view.translation() - T_mount_cam.translation()).norm();
  out.rotation_rad = RotationDistance(AX.rotation(), ZB.rotation());
  return out;
}

std::vector<Warning> DiagnoseSolution(
    const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target, const CalibrationOptions& options,
    CalibrationResult* result) {
  const size_t n = problem.dataset->cameras.size();
  struct Sums {
    double sq = 0, axzb_target = 0, axzb_camera = 0, axzb_rotation = 0;
    long points = 0;
  };
  std::vector<Sums> sums(n);
  for (CameraResult& cam : result->cameras) {
    cam.max_px = 0;
    cam.outliers = 0;
    cam.axzb = AxzbError();
  }
  // The robust loss down-weights views whose RMS is above 3 of its scales;
  // closed forms have none.
  const double outlier_px = 3.0 * result->solver.cauchy_scale_px;
  for (size_t i = 0; i < problem.views.size(); ++i) {
    const View& view = problem.views[i];
    ViewResult& vr = result->views[i];
    const int k = view.camera;
    vr.rms_px = vr.max_px = 0;
    vr.outlier = false;
    if (!T_cam_mount[k]) continue;
    const auto errors = ViewErrors(problem, view, *T_cam_mount[k], T_holder_target[k]);
    vr.rms_px = ViewRms(errors, &vr.max_px);
    vr.outlier = view.used && outlier_px > 0 && vr.rms_px > outlier_px;
    if (!view.used) continue;
    CameraResult& cam = result->cameras[k];
    for (double e : errors) sums[k].sq += e * e;
    sums[k].points += static_cast<long>(errors.size());
    cam.max_px = std::max(cam.max_px, vr.max_px);
    cam.outliers += vr.outlier ? 1 : 0;
    if (view.T_cam_target) {
      const AxzbOfView axzb = Axzb(*view.T_cam_target, *T_cam_mount[k],
                                   problem.T_mount_holder[view.pose], T_holder_target[k]);
      sums[k].axzb_target += axzb.target_frame_m;
      sums[k].axzb_camera += axzb.camera_frame_m;
      sums[k].axzb_rotation += axzb.rotation_rad;
      ++cam.axzb.views;
    }
  }
  Sums total;
  int axzb_views = 0;
  const Method closed_form = ComparisonMethod(result->method);
  for (size_t k = 0; k < n; ++k) {
    CameraResult& cam = result->cameras[k];
    cam.rms_px = sums[k].points ? std::sqrt(sums[k].sq / sums[k].points) : 0.0;
    total.sq += sums[k].sq;
    total.points += sums[k].points;
    if (cam.axzb.views) {
      cam.axzb.target_frame_mm = 1000.0 * sums[k].axzb_target / cam.axzb.views;
      cam.axzb.camera_frame_mm = 1000.0 * sums[k].axzb_camera / cam.axzb.views;
      cam.axzb.rotation_deg = kRadToDeg * sums[k].axzb_rotation / cam.axzb.views;
      total.axzb_target += sums[k].axzb_target;
      total.axzb_camera += sums[k].axzb_camera;
      total.axzb_rotation += sums[k].axzb_rotation;
      axzb_views += cam.axzb.views;
    }
    const RobotMotions motions = CollectRobotMotions(problem, problem.camera_views[k]);
    cam.rotation_spread_deg = motions.largest_deg;
    cam.axis_spread_deg = AxisSpreadDeg(motions.axes);
    cam.closed_form.reset();
  }
  // A closed form of every camera on all its views: on `threads` threads.
  if (options.compare_closed_form)
    ParallelFor(n, options.threads, [&](std::size_t k) {
      if (T_cam_mount[k])
        result->cameras[k].closed_form = CompareWithClosedForm(
            problem, static_cast<int>(k), *T_cam_mount[k], T_holder_target[k], closed_form);
    });
  result->metrics.rms_px = total.points ? std::sqrt(total.sq / total.points) : 0.0;
  result->metrics.axzb_translation_mm = axzb_views ? 1000.0 * total.axzb_target / axzb_views : 0.0;
  result->metrics.axzb_camera_translation_mm =
      axzb_views ? 1000.0 * total.axzb_camera / axzb_views : 0.0;
  result->metrics.axzb_rotation_deg =
      axzb_views ? kRadToDeg * total.axzb_rotation / axzb_views : 0.0;
  return QualityWarnings(problem, options, *result, T_cam_mount, T_holder_target);
}

}  // namespace handeye::internal

namespace handeye {

std::vector<Warning> Diagnose(const Dataset& dataset, const CalibrationOptions& options,
                              CalibrationResult* result) {
  if (result->setup != dataset.setup)
    throw InputError("", "/setup",
                     std::string("the result's setup to match the dataset's (result ") +
                         SetupName(result->setup) + ", dataset " + SetupName(dataset.setup) + ")");
  // The result's cameras in the dataset's order, with the intrinsics it used.
  Dataset working = dataset;
  std::vector<CameraResult> cameras;
  for (Camera& camera : working.cameras) {
    const auto found = std::find_if(result->cameras.begin(), result->cameras.end(),
                                    [&](const CameraResult& c) { return c.name == camera.name; });
    if (found == result->cameras.end() || result->cameras.size() != dataset.cameras.size())
      throw InputError("", "/cameras",
                       "the result to have the cameras of the dataset, camera '" + camera.name +
                           "' among them; was it computed from another dataset?");
    if (found->intrinsics) camera = found->intrinsics->camera;
    cameras.push_back(*found);
  }
  internal::Problem problem = internal::BuildProblem(working, options);
  std::map<std::pair<std::string, std::string>, const ViewResult*> given;
  for (const ViewResult& view : result->views) given[{view.pose_id, view.camera}] = &view;
  std::vector<ViewResult> views;
  for (internal::View& view : problem.views) {
    ViewResult vr;
    vr.pose_id = view.observation->pose_id;
    vr.camera = view.observation->camera;
    vr.num_points = static_cast<int>(view.p_target.size());
    const auto found = given.find({vr.pose_id, vr.camera});
    if (found != given.end() && !found->second->used) {
      view.used = false;
      view.rejected_because = found->second->rejected_because;
    }
    // Numbered as the calibration used it.
    if (found != given.end() && found->second->flipped)
      if (const auto half_turn = internal::HalfTurnSymmetry(*working.target))
        internal::FlipView(*half_turn, &view);
    vr.used = view.used;
    vr.rejected_because = view.rejected_because;
    vr.flipped = view.flipped;
    views.push_back(vr);
  }
  internal::IndexUsedViews(&problem);
  std::vector<std::optional<Eigen::Isometry3d>> T_cam_mount(cameras.size());
  internal::TargetPoses T_holder_target(cameras.size(), result->T_target);
  for (size_t k = 0; k < cameras.size(); ++k) {
    if (cameras[k].calibrated) T_cam_mount[k] = cameras[k].T_cam.inverse();
    if (cameras[k].own_T_target) T_holder_target[k] = *cameras[k].own_T_target;
  }
  result->cameras = cameras;
  result->views = views;
  return internal::DiagnoseSolution(problem, T_cam_mount, T_holder_target, options, result);
}

}  // namespace handeye
