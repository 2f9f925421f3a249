// SPDX-License-Identifier: GPL-2.0-or-later
// The report's model: every view pushed through the calibrated chain, the
// per-camera statistics, and the warnings a person must see before accepting
// a calibration.
#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/calib3d.hpp>
#include <set>
#include <sstream>

#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "report_internal.h"

namespace handeye::report {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

std::string Fixed(double value, int decimals) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(decimals);
  out << value;
  return out.str();
}

// X_k and M_j of calibration.h's chain p_cam = X_k · M_j · Z · p_target.
Eigen::Isometry3d ChainM(const Dataset& dataset, int pose) {
  const Eigen::Isometry3d& T_base_ee = dataset.poses[pose].T_base_ee;
  return dataset.setup == Setup::kEyeToHand ? T_base_ee : T_base_ee.inverse();
}

// The Z a camera's residuals are computed with: its own for per-camera
// methods (as the solver reports them), the shared one otherwise.
Eigen::Isometry3d ChainZ(const CalibrationResult& result, const CameraResult& camera) {
  return camera.own_T_target.value_or(result.T_target);
}

std::optional<Eigen::Isometry3d> SolvePnp(const Camera& camera, const ViewModel& view) {
  if (view.p_target.size() < 4) return std::nullopt;
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (size_t i = 0; i < view.p_target.size(); ++i) {
    object.emplace_back(view.p_target[i].x(), view.p_target[i].y(), view.p_target[i].z());
    image.emplace_back(view.observation->points_px[i].x(), view.observation->points_px[i].y());
  }
  const cv::Matx33d K(camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1);
  const std::vector<double> dist = camera.Distortion();
  cv::Mat rvec, tvec;
  try {
    // Planar target: IPPE gives the pose in closed form, LM polishes it.
    if (!cv::solvePnP(object, image, K, dist, rvec, tvec, false, cv::SOLVEPNP_IPPE))
      return std::nullopt;
    cv::solvePnPRefineLM(object, image, K, dist, rvec, tvec);
  } catch (const cv::Exception&) {
    return std::nullopt;
  }
  return MakeTransformFromRotationVector(
      Eigen::Vector3d(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2)),
      Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)));
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

// Smallest 1, 2 or 5 × 10^k that is >= value.
double NiceCeil(double value) {
  if (!(value > 0)) return 1.0;
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade >= value * (1 - 1e-12)) return m * decade;
  return 10.0 * decade;
}

// Robot rotation diversity of one camera's used views (see ReportOptions).
void RotationDiversity(const Dataset& dataset, const std::vector<int>& poses, double* spread_deg,
                       double* axis_spread_deg) {
  std::vector<Eigen::Vector3d> axes;
  *spread_deg = 0;
  for (size_t a = 0; a < poses.size(); ++a)
    for (size_t b = a + 1; b < poses.size(); ++b) {
      const Eigen::Matrix3d R = dataset.poses[poses[a]].T_base_ee.rotation().transpose() *
                                dataset.poses[poses[b]].T_base_ee.rotation();
      const Eigen::Vector3d rv = RotationVectorFromMatrix(R);
      *spread_deg = std::max(*spread_deg, rv.norm() * kRadToDeg);
      // Axes of motions of a couple of degrees are noise-dominated.
      if (rv.norm() > 5.0 / kRadToDeg) axes.push_back(rv.normalized());
    }
  double best_cos = 1.0;
  for (size_t a = 0; a < axes.size(); ++a)
    for (size_t b = a + 1; b < axes.size(); ++b)
      best_cos = std::min(best_cos, std::abs(axes[a].dot(axes[b])));
  *axis_spread_deg = axes.size() < 2 ? 0.0 : std::acos(std::clamp(best_cos, 0.0, 1.0)) * kRadToDeg;
}

void CompareWithClosedForm(const ReportModel& model, Method method,
                           std::vector<CameraModel>* cameras, std::vector<std::string>* notes) {
  const Dataset& dataset = *model.dataset;
  CalibrationOptions options;
  options.method = method;
  CalibrationResult closed;
  try {
    closed = Calibrate(dataset, options);
  } catch (const std::exception& e) {
    notes->push_back(std::string("no per-camera closed-form comparison: ") + MethodName(method) +
                     " failed: " + e.what());
    for (auto& cam : *cameras)
      cam.closed_form.why_not = MethodName(method) + std::string(" failed");
    return;
  }
  for (size_t k = 0; k < cameras->size(); ++k) {
    CameraModel& cam = (*cameras)[k];
    const CameraResult& cf = closed.cameras[k];
    if (!cam.result->calibrated) {
      cam.closed_form.why_not = "not calibrated";
      continue;
    }
    if (!cf.calibrated) {
      cam.closed_form.why_not = std::string(MethodName(method)) + " could not calibrate it";
      continue;
    }
    ClosedFormComparison& cmp = cam.closed_form;
    cmp.available = true;
    cmp.translation_mm = 1000.0 * (cf.T_cam.translation() - cam.result->T_cam.translation()).norm();
    cmp.rotation_deg =
        RotationDistance(cf.T_cam.rotation(), cam.result->T_cam.rotation()) * kRadToDeg;
    // The camera pose difference in pixels: the same target points (placed by
    // the result's chain) seen from the closed form's camera pose. Each
    // method's own chain would not do: a closed form's error in X is largely
    // made up by its own Z, so its predictions agree while X does not.
    const Eigen::Isometry3d X_cf = cf.T_cam.inverse();
    const Eigen::Isometry3d X = cam.result->T_cam.inverse();
    double sum = 0;
    int n = 0;
    for (int v : cam.views) {
      const ViewModel& view = model.views[v];
      if (!view.used || !view.T_cam_target) continue;
      const auto closed_px =
          ProjectAll(*cam.camera, X_cf * X.inverse() * *view.T_cam_target, view.p_target);
      for (size_t i = 0; i < closed_px.size(); ++i) {
        if (!closed_px[i] || !view.predicted_px[i]) continue;
        sum += (*closed_px[i] - *view.predicted_px[i]).norm();
        ++n;
      }
    }
    cmp.displacement_px = n ? sum / n : 0.0;
  }
}

void AddWarnings(const ReportOptions& options, ReportModel* model) {
  const CalibrationResult& result = *model->result;
  auto& warnings = model->warnings;
  if (!result.solver.converged)
    warnings.push_back("the solver did not converge (" +
                       (result.solver.termination.empty() ? std::string("no reason given")
                                                          : result.solver.termination) +
                       "): the numbers below are not a calibration");
  for (const CameraModel& cam : model->cameras) {
    const std::string name = "camera '" + cam.camera->name + "'";
    if (!cam.result->calibrated) {
      warnings.push_back(name + " is not calibrated (" + std::to_string(cam.used) +
                         " usable views)");
      continue;
    }
    if (cam.used < options.min_views_per_camera)
      warnings.push_back(name + ": few views, only " + std::to_string(cam.used) +
                         " used (fewer than " + std::to_string(options.min_views_per_camera) +
                         "); one bad pose moves its result visibly; add robot poses in its view");
    if (cam.rotation_spread_deg < options.min_rotation_spread_deg)
      warnings.push_back(
          name + ": poor rotation diversity, its views differ in robot rotation by at most " +
          Fixed(cam.rotation_spread_deg, 1) + "° (< " + Fixed(options.min_rotation_spread_deg, 0) +
          "°); tilt the target more between poses");
    else if (cam.axis_spread_deg < options.min_axis_spread_deg)
      warnings.push_back(
          name + ": poor rotation diversity, the robot motions between its views turn about " +
          "nearly one axis (largest angle between axes " + Fixed(cam.axis_spread_deg, 1) + "° < " +
          Fixed(options.min_axis_spread_deg, 0) + "°); rotate about a second axis too");
    if (cam.rms_px > options.max_camera_rms_px)
      warnings.push_back(name + ": large residuals, RMS " + Fixed(cam.rms_px, 2) +
                         " px through the calibrated chain (> " +
                         Fixed(options.max_camera_rms_px, 2) + " px)");
    if (cam.outliers > 0) {
      std::string list;
      int listed = 0;
      for (int v : cam.views) {
        const ViewModel& view = model->views[v];
        if (!view.outlier) continue;
        if (listed++ == 5) {
          list += ", …";
          break;
        }
        list += (list.empty() ? "" : ", ") + std::string("pose ") + view.observation->pose_id +
                " (RMS " + Fixed(view.rms_px, 2) + " px)";
      }
      warnings.push_back(name + ": " + std::to_string(cam.outliers) +
                         (cam.outliers == 1 ? " view" : " views") +
                         " down-weighted as outliers by the solver: " + list);
    }
    const ClosedFormComparison& cf = cam.closed_form;
    if (cf.available && cf.displacement_px > options.max_closed_form_disagreement_px)
      warnings.push_back(name + ": the result and " + model->closed_form_method +
                         "'s per-camera closed form disagree by " + Fixed(cf.displacement_px, 1) +
                         " px in the image (" + Fixed(cf.translation_mm, 1) + " mm, " +
                         Fixed(cf.rotation_deg, 2) + "°; threshold " +
                         Fixed(options.max_closed_form_disagreement_px, 0) +
                         " px); check this camera's robot poses and views");
  }
  for (const auto& w : result.warnings) warnings.push_back("calibration: " + w);
}

}  // namespace

Eigen::Vector3d RollPitchYawDeg(const Eigen::Matrix3d& R) {
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double roll = std::atan2(R(2, 1), R(2, 2));
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  return kRadToDeg * Eigen::Vector3d(roll, pitch, yaw);
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
    if (found != view_results.end()) {
      view.used = found->second->used;
      view.outlier = found->second->outlier;
      view.rejected_because = found->second->rejected_because;
    } else if (!result.views.empty()) {
      ++missing_from_result;
    }
    if (cam.result->calibrated) {
      view.T_cam_target =
          cam.result->T_cam.inverse() * ChainM(dataset, view.pose) * ChainZ(result, *cam.result);
      view.predicted_px = ProjectAll(*cam.camera, *view.T_cam_target, view.p_target);
      view.rms_px = Rms(view.predicted_px, obs.points_px, &view.max_px, &view.residual_px);
    }
    view.T_cam_target_pnp = SolvePnp(*cam.camera, view);
    const std::string base = cam.folder + "/" + SafeFileName(obs.pose_id);
    std::string unique = base;
    while (!thumb_names.insert(unique).second) unique += "_";
    view.overlay_path = "overlays/" + unique + ".png";
    view.thumb_path = "thumbs/" + unique + ".jpg";
    model.views.push_back(std::move(view));
  }
  if (missing_from_result > 0)
    model.warnings.push_back(
        std::to_string(missing_from_result) +
        " views of the observations are not in the result: it was computed from other "
        "observations (they are drawn, but not as the solver saw them)");

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

  // Per-camera statistics over the used views.
  std::vector<double> all_residuals;
  for (size_t k = 0; k < model.cameras.size(); ++k) {
    CameraModel& cam = model.cameras[k];
    double sq = 0;
    int n = 0;
    std::vector<int> poses;
    for (size_t i = 0; i < model.views.size(); ++i) {
      const ViewModel& view = model.views[i];
      if (view.camera != static_cast<int>(k)) continue;
      cam.views.push_back(static_cast<int>(i));
      if (!view.used) {
        ++cam.rejected;
        continue;
      }
      ++cam.used;
      cam.outliers += view.outlier ? 1 : 0;
      poses.push_back(view.pose);
      for (double e : view.residual_px) {
        sq += e * e;
        ++n;
        cam.max_px = std::max(cam.max_px, e);
        all_residuals.push_back(e);
      }
      if (view.T_cam_target && view.T_cam_target_pnp) {
        // The paper's AX = ZB check (as the solver's metrics): both sides are
        // T_target_base (eye_to_hand) or T_target_ee (eye_in_hand).
        const Eigen::Isometry3d X = cam.result->T_cam.inverse();
        const Eigen::Isometry3d Z = ChainZ(result, *cam.result);
        const Eigen::Isometry3d AX = view.T_cam_target_pnp->inverse() * X;
        const Eigen::Isometry3d ZB = Z.inverse() * ChainM(dataset, view.pose).inverse();
        cam.axzb_translation_mm += 1000.0 * (AX.translation() - ZB.translation()).norm();
        cam.axzb_rotation_deg += RotationDistance(AX.rotation(), ZB.rotation()) * kRadToDeg;
        ++cam.axzb_views;
      }
    }
    cam.rms_px = n ? std::sqrt(sq / n) : 0.0;
    if (cam.axzb_views) {
      cam.axzb_translation_mm /= cam.axzb_views;
      cam.axzb_rotation_deg /= cam.axzb_views;
    }
    RotationDiversity(dataset, poses, &cam.rotation_spread_deg, &cam.axis_spread_deg);
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

  if (options.compare_closed_form) {
    const Method method = result.method == Method::kPark ? Method::kVisp : Method::kPark;
    model.closed_form_method = method == Method::kPark ? "Park" : "ViSP";
    CompareWithClosedForm(model, method, &model.cameras, &model.notes);
  }
  AddWarnings(options, &model);
  return model;
}

}  // namespace handeye::report
