// SPDX-License-Identifier: GPL-2.0-or-later
// The report's model: every view pushed through the calibrated chain, for
// drawing. The figures and warnings are the result's (Calibrate() computed
// them, handeye/core/diagnostics.h); the report recomputes none of them.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "handeye/core/error.h"
#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"
#include "report_internal.h"

namespace handeye::report {
namespace {

// T_mount_holder of a pose in the chain T_cam_target = T_cam_mount · T_mount_holder · T_holder_target.
Eigen::Isometry3d ChainM(const Dataset& dataset, int pose) {
  return FramesOf(dataset.setup).MountFromHolder(dataset.poses[pose].T_base_ee);
}

// The Z a camera's residuals are computed with: its own for per-camera
// methods (as the solver reports them), the shared one otherwise.
Eigen::Isometry3d ChainZ(const CalibrationResult& result, const CameraResult& camera) {
  return camera.own_T_target.value_or(result.T_target);
}

std::vector<std::optional<Eigen::Vector2d>> ProjectAll(
    const Camera& camera, const Eigen::Isometry3d& T_cam_target,
    const std::vector<Eigen::Vector3d>& p_target) {
  std::vector<std::optional<Eigen::Vector2d>> out;
  out.reserve(p_target.size());
  for (const auto& p : p_target) out.push_back(camera.Project(T_cam_target * p));
  return out;
}

// RMS of detected − predicted over the points that project.
double Rms(const std::vector<std::optional<Eigen::Vector2d>>& predicted,
           const std::vector<Eigen::Vector2d>& detected, double* max_px = nullptr,
           std::vector<double>* each = nullptr) {
  double sum = 0, worst = 0;
  int n = 0;
  for (size_t i = 0; i < predicted.size(); ++i) {
    if (!predicted[i]) continue;
    const double e = (*predicted[i] - detected[i]).norm();
    sum += e * e;
    worst = std::max(worst, e);
    ++n;
    if (each) each->push_back(e);
  }
  if (max_px) *max_px = worst;
  return n ? std::sqrt(sum / n) : 0.0;
}

}  // namespace

double NiceCeil(double value) {
  if (!(value > 0) || !std::isfinite(value)) return 1.0;
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade >= value * (1 - 1e-12)) return m * decade;
  return 10.0 * decade;
}

double NiceFloor(double value) {
  if (!(value > 0) || !std::isfinite(value)) return 1.0;
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * decade <= value * (1 + 1e-12)) return m * decade;
  return decade;
}

std::string SafeFileName(const std::string& name) {
  std::string out;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '_' || c == '-';
    out += ok ? c : '_';
  }
  if (out.empty() || out == "." || out == "..") out = "_" + out;
  return out;
}

ReportModel BuildModel(const Dataset& dataset, const CalibrationResult& result,
                       const ReportOptions& options) {
  if (!dataset.target) throw InputError("", "/target", "a dataset with a target");
  if (result.setup != dataset.setup)
    throw InputError("", "/setup",
                     std::string("the result's setup to match the dataset's (result ") +
                         SetupName(result.setup) + ", dataset " + SetupName(dataset.setup) + ")");
  ReportModel model;
  model.dataset = &dataset;
  model.result = &result;

  // Cameras: the result must describe exactly the dataset's cameras.
  std::set<std::string> folders;
  for (size_t k = 0; k < dataset.cameras.size(); ++k) {
    CameraModel cam;
    cam.camera = &dataset.cameras[k];
    for (const CameraResult& r : result.cameras)
      if (r.name == cam.camera->name) cam.result = &r;
    if (!cam.result)
      throw InputError("", "/cameras",
                       "the result to have camera '" + cam.camera->name +
                           "' of the dataset; was it computed from another dataset?");
    cam.folder = SafeFileName(cam.camera->name);
    while (!folders.insert(cam.folder).second) cam.folder += "_";
    model.cameras.push_back(cam);
  }
  for (const CameraResult& r : result.cameras)
    if (dataset.CameraIndex(r.name) < 0)
      throw InputError("", "/cameras/" + r.name,
                       "a camera of the dataset; the dataset has no camera '" + r.name + "'");

  std::map<std::pair<std::string, std::string>, const ViewResult*> view_results;
  for (const ViewResult& v : result.views) view_results[{v.pose_id, v.camera}] = &v;
  std::map<std::pair<int, int>, Eigen::Isometry3d> pairs;  // (k, t) → T_camk_camt
  for (const CameraPairResult& p : result.camera_pairs) {
    const int k = dataset.CameraIndex(p.camera_k), t = dataset.CameraIndex(p.camera_t);
    if (k < 0 || t < 0) continue;
    pairs[{k, t}] = p.T_camk_camt;
    pairs.emplace(std::make_pair(t, k), p.T_camk_camt.inverse());
  }

  // Views through the chain.
  int missing_from_result = 0;
  std::set<std::string> thumb_names;
  for (const Observation& obs : dataset.observations) {
    ViewModel view;
    view.camera = dataset.CameraIndex(obs.camera);
    view.pose = dataset.PoseIndex(obs.pose_id);
    if (view.camera < 0 || view.pose < 0)
      throw InputError("", "/observations",
                       "observations of the dataset's cameras and poses; got camera '" +
                           obs.camera + "', pose '" + obs.pose_id + "'");
    if (obs.ids.size() != obs.points_px.size())
      throw InputError("", "/observations", "as many points_px as ids");
    view.observation = &obs;
    for (int id : obs.ids) {
      const TargetPoint* p = dataset.target->FindPoint(id);
      if (!p)
        throw InputError("", "/observations",
                         "ids of the target's points; got " + std::to_string(id));
      view.p_target.push_back(p->p_target);
    }
    const CameraModel& cam = model.cameras[view.camera];
    const auto found = view_results.find({obs.pose_id, obs.camera});
    if (cam.result->calibrated) {
      view.T_cam_target =
          cam.result->T_cam.inverse() * ChainM(dataset, view.pose) * ChainZ(result, *cam.result);
      view.predicted_px = ProjectAll(*cam.camera, *view.T_cam_target, view.p_target);
      view.rms_px = Rms(view.predicted_px, obs.points_px, &view.max_px, &view.residual_px);
    }
    if (found != view_results.end()) {
      view.used = found->second->used;
      view.outlier = found->second->outlier;
      view.rejected_because = found->second->rejected_because;
      view.rms_px = found->second->rms_px;
      view.max_px = found->second->max_px;
    } else if (!result.views.empty()) {
      ++missing_from_result;
    }
    const std::string base = cam.folder + "/" + SafeFileName(obs.pose_id);
    std::string unique = base;
    while (!thumb_names.insert(unique).second) unique += "_";
    view.overlay_path = "overlays/" + unique + ".png";
    view.thumb_path = "thumbs/" + unique + ".jpg";
    model.views.push_back(std::move(view));
  }
  if (missing_from_result > 0)
    model.warnings.push_back(GeneralWarning(
        WarningKind::kResultViewsMissing,
        std::to_string(missing_from_result) +
        " views of the observations are not in the result: it was computed from other "
        "observations (they are drawn, but not as the solver saw them)"));

  // Cross-camera predictions, for the views the solver tied together (used
  // views of two cameras at one pose).
  std::map<int, std::vector<int>> used_at_pose;
  for (size_t i = 0; i < model.views.size(); ++i)
    if (model.views[i].used) used_at_pose[model.views[i].pose].push_back(static_cast<int>(i));
  for (ViewModel& view : model.views) {
    for (int other : used_at_pose[view.pose]) {
      const int t = model.views[other].camera;
      const CameraResult& cam_t = *model.cameras[t].result;
      const auto pair = pairs.find({view.camera, t});
      if (t == view.camera || pair == pairs.end() || !cam_t.calibrated) continue;
      CrossPrediction cross;
      cross.other_camera = t;
      const Eigen::Isometry3d T_camk_target =
          pair->second * cam_t.T_cam.inverse() * ChainM(dataset, view.pose) * ChainZ(result, cam_t);
      cross.predicted_px =
          ProjectAll(*model.cameras[view.camera].camera, T_camk_target, view.p_target);
      cross.rms_px = Rms(cross.predicted_px, view.observation->points_px);
      view.cross.push_back(std::move(cross));
    }
  }

  // Each camera's views, and the residuals of the used ones for the colour scale.
  std::vector<double> all_residuals;
  for (size_t i = 0; i < model.views.size(); ++i) {
    const ViewModel& view = model.views[i];
    CameraModel& cam = model.cameras[view.camera];
    cam.views.push_back(static_cast<int>(i));
    if (!view.used) {
      ++cam.rejected;
      continue;
    }
    ++cam.used;
    // A non-finite residual (a NaN in the data) has no place on a scale.
    for (double r : view.residual_px)
      if (std::isfinite(r)) all_residuals.push_back(r);
  }

  // One colour scale for the whole report: up to the 99th percentile of the
  // residuals (so one wild point does not wash out the rest), at least 1 px
  // (so a good calibration looks green, not a rainbow of 0.1 px differences).
  if (!all_residuals.empty()) {
    const size_t at = static_cast<size_t>(0.99 * (all_residuals.size() - 1));
    std::nth_element(all_residuals.begin(), all_residuals.begin() + at, all_residuals.end());
    model.residual_p99_px = all_residuals[at];
    model.residual_scale_max_px = std::max(1.0, NiceCeil(all_residuals[at]));
  }

  model.show_closed_form = options.compare_closed_form;
  model.warnings.insert(model.warnings.end(), result.warnings.begin(), result.warnings.end());
  return model;
}

}  // namespace handeye::report
