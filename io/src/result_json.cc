// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/result_json.h"
#include "handeye/io/dataset_json.h"

#include <algorithm>
#include <cmath>

#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"
#include "handeye/io/atomic_file.h"
#include "handeye/io/json_util.h"
#include "handeye/io/warning_json.h"

namespace handeye {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// Summaries for people: millimetres, fixed-axis roll/pitch/yaw (x, y, z; R =
// Rz(yaw)·Ry(pitch)·Rx(roll)) in degrees, and the quaternion.
void AddSummary(const Eigen::Isometry3d& T, nlohmann::ordered_json* out) {
  const Eigen::Vector3d t = 1000.0 * T.translation();
  const Eigen::Matrix3d R = T.rotation();
  const Eigen::Vector3d rpy = kRadToDeg * RollPitchYaw(R);
  Eigen::Quaterniond q(R);
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  (*out)["translation_mm"] = {t.x(), t.y(), t.z()};
  (*out)["rpy_deg"] = {rpy.x(), rpy.y(), rpy.z()};
  (*out)["quaternion_xyzw"] = {q.x(), q.y(), q.z(), q.w()};
}

bool ReadBool(const JsonReader& value) {
  if (!value.present() || !value.json().is_boolean()) throw value.Error("true or false");
  return value.json().get<bool>();
}

nlohmann::ordered_json Matrix6Json(const Eigen::Matrix<double, 6, 6>& m) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int r = 0; r < 6; ++r) {
    nlohmann::ordered_json row = nlohmann::ordered_json::array();
    for (int c = 0; c < 6; ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

nlohmann::ordered_json SigmaJson(const PoseUncertainty& sigma) {
  // The views' own part, what a capture again with the same intrinsics
  // would scatter by: the yardstick of a leave-out spread (bench/leave-out).
  nlohmann::ordered_json out = {{"position_mm", sigma.position_mm},
                                {"rotation_deg", sigma.rotation_deg},
                                {"own_position_mm", sigma.OwnPositionMm()},
                                {"own_rotation_deg", sigma.OwnRotationDeg()},
                                {"covariance", Matrix6Json(sigma.covariance)}};
  if (!sigma.from_given_intrinsics.isZero()) out["covariance_from_given_intrinsics"] = Matrix6Json(sigma.from_given_intrinsics);
  if (sigma.covariance_with_target)
    out["covariance_with_target"] = Matrix6Json(*sigma.covariance_with_target);
  return out;
}

Eigen::Matrix<double, 6, 6> ReadMatrix6(const JsonReader& rows) {
  Eigen::Matrix<double, 6, 6> m;
  if (rows.ArraySize("a 6×6 array") != 6) throw rows.Error("a 6×6 array");
  for (int row = 0; row < 6; ++row) {
    const JsonReader values = rows.At(row);
    if (values.ArraySize("a row of 6 numbers") != 6) throw values.Error("a row of 6 numbers");
    for (int c = 0; c < 6; ++c) m(row, c) = values.At(c).Number();
  }
  return m;
}

PoseUncertainty ReadSigma(const JsonReader& r) {
  PoseUncertainty sigma;
  sigma.position_mm = r.Key("position_mm").Number();
  sigma.rotation_deg = r.Key("rotation_deg").Number();
  sigma.covariance = ReadMatrix6(r.Key("covariance"));
  if (r.Has("covariance_from_given_intrinsics"))
    sigma.from_given_intrinsics = ReadMatrix6(r.Key("covariance_from_given_intrinsics"));
  if (r.Has("covariance_with_target"))
    sigma.covariance_with_target = ReadMatrix6(r.Key("covariance_with_target"));
  return sigma;
}

// The refined intrinsics in the dataset's form, their 1σ and what was refined.
void AddIntrinsics(const IntrinsicsResult& intrinsics, nlohmann::ordered_json* c) {
  (*c)["image_size"] = {intrinsics.camera.width, intrinsics.camera.height};
  WriteIntrinsicsJson(intrinsics.camera, c);
  const auto& s = intrinsics.sigma;
  nlohmann::ordered_json sigma = {{"fx", s[0]}, {"fy", s[1]}, {"cx", s[2]}, {"cy", s[3]}};
  if (intrinsics.camera.num_distortion > 0)
    sigma["distortion"] = std::vector<double>(s.begin() + 4, s.begin() + 4 + intrinsics.camera.num_distortion);
  (*c)["intrinsics_sigma"] = sigma;
  (*c)["intrinsics_refined"] = intrinsics.refined;
  if (!intrinsics.undetermined.empty()) (*c)["intrinsics_undetermined"] = intrinsics.undetermined;
}

std::vector<std::string> ReadStrings(const JsonReader& list) {
  std::vector<std::string> out;
  const size_t n = list.ArraySize("an array of strings");
  for (size_t i = 0; i < n; ++i) out.push_back(list.At(i).String());
  return out;
}

IntrinsicsResult ReadIntrinsicsResult(const JsonReader& cam, const std::string& name) {
  IntrinsicsResult out;
  const JsonReader size = cam.Key("image_size");
  if (size.ArraySize("[width, height] in pixels") != 2) throw size.Error("[width, height] in pixels");
  out.camera = ReadIntrinsicsJson(cam, name, size.At(0).Int(1, 1 << 20), size.At(1).Int(1, 1 << 20));
  const JsonReader sigma = cam.Key("intrinsics_sigma");
  const char* keys[] = {"fx", "fy", "cx", "cy"};
  for (int p = 0; p < 4; ++p) out.sigma[p] = sigma.Key(keys[p]).Number();
  if (sigma.Has("distortion")) {
    const JsonReader d = sigma.Key("distortion");
    const size_t n = std::min<size_t>(d.ArraySize("an array of numbers"), OpenCVCameraModel::kNumDistortion);
    for (size_t i = 0; i < n; ++i) out.sigma[4 + i] = d.At(i).Number();
  }
  if (cam.Has("intrinsics_refined")) out.refined = ReadStrings(cam.Key("intrinsics_refined"));
  if (cam.Has("intrinsics_undetermined")) out.undetermined = ReadStrings(cam.Key("intrinsics_undetermined"));
  return out;
}

// The diagnostics Calibrate() computed for a camera (handeye/core/diagnostics.h).
void AddDiagnostics(const CameraResult& cam, Setup setup, nlohmann::ordered_json* c) {
  (*c)["max_px"] = cam.max_px;
  (*c)["outliers"] = cam.outliers;
  (*c)["axzb"] = {{"translation_mm", cam.axzb.camera_frame_mm},
                  {"frame", FramesOf(setup).mount},
                  {"target_frame_translation_mm", cam.axzb.target_frame_mm},
                  {"rotation_deg", cam.axzb.rotation_deg},
                  {"views", cam.axzb.views}};
  (*c)["rotation_spread_deg"] = cam.rotation_spread_deg;
  (*c)["axis_spread_deg"] = cam.axis_spread_deg;
  if (!cam.closed_form) return;
  const ClosedFormComparison& cf = *cam.closed_form;
  if (cf.available)
    (*c)["closed_form"] = {{"method", cf.method},
                           {"translation_mm", cf.translation_mm},
                           {"rotation_deg", cf.rotation_deg},
                           {"displacement_px", cf.displacement_px}};
  else
    (*c)["closed_form"] = {{"method", cf.method}, {"why_not", cf.why_not}};
}

void ReadDiagnostics(const JsonReader& c, CameraResult* cam) {
  if (c.Has("max_px")) cam->max_px = c.Key("max_px").Number();
  if (c.Has("outliers")) cam->outliers = c.Key("outliers").Int(0);
  if (c.Has("axzb")) {
    const JsonReader axzb = c.Key("axzb");
    cam->axzb.camera_frame_mm = axzb.Key("translation_mm").Number();
    cam->axzb.target_frame_mm = axzb.Key("target_frame_translation_mm").Number();
    cam->axzb.rotation_deg = axzb.Key("rotation_deg").Number();
    cam->axzb.views = axzb.Key("views").Int(0);
  }
  if (c.Has("rotation_spread_deg")) cam->rotation_spread_deg = c.Key("rotation_spread_deg").Number();
  if (c.Has("axis_spread_deg")) cam->axis_spread_deg = c.Key("axis_spread_deg").Number();
  if (c.Has("closed_form")) {
    const JsonReader cf = c.Key("closed_form");
    ClosedFormComparison cmp;
    cmp.method = cf.Key("method").String();
    cmp.available = !cf.Has("why_not");
    if (cmp.available) {
      cmp.translation_mm = cf.Key("translation_mm").Number();
      cmp.rotation_deg = cf.Key("rotation_deg").Number();
      cmp.displacement_px = cf.Key("displacement_px").Number();
    } else {
      cmp.why_not = cf.Key("why_not").String();
    }
    cam->closed_form = cmp;
  }
}

// The options that shaped the result (the method is the file's "method").
nlohmann::ordered_json OptionsJson(const CalibrationOptions& o) {
  const QualityThresholds& w = o.warn;
  return {{"cauchy_scale_px", o.cauchy_scale_px},
          {"cross_terms", o.cross_terms},
          {"reject_views", o.reject_views},
          {"pnp_max_rms_px", o.pnp_max_rms_px},
          {"robot_sigma_mm", o.robot_sigma_mm},
          {"robot_sigma_deg", o.robot_sigma_deg},
          {"refine_intrinsics", o.refine_intrinsics},
          {"intrinsics_sigma", JsonFromIntrinsicsSigma(o.intrinsics_sigma)},
          {"compare_closed_form", o.compare_closed_form},
          {"warn",
           {{"min_views_per_camera", w.min_views_per_camera},
            {"min_rotation_spread_deg", w.min_rotation_spread_deg},
            {"min_axis_spread_deg", w.min_axis_spread_deg},
            {"max_camera_rms_px", w.max_camera_rms_px},
            {"max_closed_form_disagreement_px", w.max_closed_form_disagreement_px}}}};
}

void ReadOptions(const JsonReader& r, CalibrationOptions* o) {
  o->cauchy_scale_px = r.Key("cauchy_scale_px").Number();
  o->cross_terms = ReadBool(r.Key("cross_terms"));
  o->reject_views = ReadBool(r.Key("reject_views"));
  o->pnp_max_rms_px = r.Key("pnp_max_rms_px").Number();
  o->robot_sigma_mm = r.Key("robot_sigma_mm").Number();
  o->robot_sigma_deg = r.Key("robot_sigma_deg").Number();
  o->refine_intrinsics = static_cast<unsigned>(r.Key("refine_intrinsics").Int(0, kAllIntrinsics));
  if (r.Has("intrinsics_sigma")) {  // results written before it took the given intrinsics as exact
    const JsonReader s = r.Key("intrinsics_sigma");
    o->intrinsics_sigma.focal_percent = s.Key("focal_percent").Number();
    o->intrinsics_sigma.principal_point_px = s.Key("principal_point_px").Number();
  } else {
    o->intrinsics_sigma = GivenIntrinsicsSigma{0.0, 0.0};
  }
  o->compare_closed_form = ReadBool(r.Key("compare_closed_form"));
  const JsonReader w = r.Key("warn");
  o->warn.min_views_per_camera = w.Key("min_views_per_camera").Int(0);
  o->warn.min_rotation_spread_deg = w.Key("min_rotation_spread_deg").Number();
  o->warn.min_axis_spread_deg = w.Key("min_axis_spread_deg").Number();
  o->warn.max_camera_rms_px = w.Key("max_camera_rms_px").Number();
  o->warn.max_closed_form_disagreement_px = w.Key("max_closed_form_disagreement_px").Number();
}

}  // namespace

std::string ResultJson(const CalibrationResult& result) {
  nlohmann::ordered_json root;
  root["format"] = "handeye-result/1";
  root["setup"] = SetupName(result.setup);
  const SetupFrames frames = FramesOf(result.setup);
  root["method"] = MethodName(result.method);
  nlohmann::ordered_json cameras = nlohmann::ordered_json::object();
  for (const CameraResult& cam : result.cameras) {
    nlohmann::ordered_json c;
    c["calibrated"] = cam.calibrated;
    if (cam.calibrated) {
      c[frames.camera_key] = JsonFromTransform(cam.T_cam);
      AddSummary(cam.T_cam, &c);
      if (cam.own_T_target) c[frames.target_key] = JsonFromTransform(*cam.own_T_target);
      c["rms_px"] = cam.rms_px;
      if (cam.sigma) c["sigma"] = SigmaJson(*cam.sigma);
      if (cam.given_intrinsics_offset_px) {
        const Eigen::Vector4d& d = *cam.given_intrinsics_offset_px;
        c["given_intrinsics_offset_px"] = {{"fx", d[0]}, {"fy", d[1]}, {"cx", d[2]}, {"cy", d[3]}};
      }
      if (cam.cross_validation)
        c["cross_validation"] = {{"folds", cam.cross_validation->folds},
                                 {"held_out_rms_px", cam.cross_validation->held_out_rms_px},
                                 {"position_spread_mm", cam.cross_validation->position_spread_mm},
                                 {"rotation_spread_deg", cam.cross_validation->rotation_spread_deg}};
      if (cam.intrinsics) AddIntrinsics(*cam.intrinsics, &c);
      AddDiagnostics(cam, result.setup, &c);
    }
    c["views"] = cam.views;
    c["views_rejected"] = cam.views_rejected;
    cameras[cam.name] = c;
  }
  root["cameras"] = cameras;
  root[frames.target_key] = JsonFromTransform(result.T_target);
  nlohmann::ordered_json target_summary;
  AddSummary(result.T_target, &target_summary);
  root[frames.target_key + "_summary"] = target_summary;
  if (result.target_sigma) root[frames.target_key + "_sigma"] = SigmaJson(*result.target_sigma);
  nlohmann::ordered_json pairs = nlohmann::ordered_json::object();
  for (const CameraPairResult& p : result.camera_pairs) {
    nlohmann::ordered_json entry;
    entry["T_" + p.camera_k + "_" + p.camera_t] = JsonFromTransform(p.T_camk_camt);
    entry["shared_views"] = p.shared_views;
    pairs[p.camera_k + "/" + p.camera_t] = entry;
  }
  root["camera_pairs"] = pairs;
  root["metrics"] = {{"rms_px", result.metrics.rms_px},
                     {"axzb_translation_mm", result.metrics.axzb_translation_mm},
                     {"axzb_translation_frame", "target"},
                     {"axzb_rotation_deg", result.metrics.axzb_rotation_deg},
                     {"axzb_camera_translation_mm", result.metrics.axzb_camera_translation_mm},
                     {"axzb_camera_frame", frames.mount}};
  root["solver"] = {{"seconds", result.solver.seconds},
                    {"iterations", result.solver.iterations},
                    {"converged", result.solver.converged},
                    {"termination", result.solver.termination},
                    {"cauchy_scale_px", result.solver.cauchy_scale_px},
                    {"rounds", result.solver.rounds},
                    {"robot_sigma_mm", result.solver.robot_sigma_mm},
                    {"robot_sigma_deg", result.solver.robot_sigma_deg},
                    {"robot_sigma_solved_mm", result.solver.robot_sigma_solved_mm},
                    {"robot_sigma_solved_deg", result.solver.robot_sigma_solved_deg}};
  if (result.solver.model) {
    nlohmann::ordered_json candidates = nlohmann::ordered_json::array();
    for (const ModelCandidate& m : result.solver.model->candidates)
      candidates.push_back({{"name", m.name},
                            {"held_out_rms_px", m.held_out_rms_px},
                            {"points", m.points},
                            {"robot_sigma_mm", m.robot_sigma_mm},
                            {"robot_sigma_deg", m.robot_sigma_deg}});
    root["solver"]["model"] = {{"chosen", result.solver.model->chosen},
                               {"folds", result.solver.model->folds},
                               {"candidates", candidates}};
  }
  nlohmann::ordered_json views = nlohmann::ordered_json::array();
  for (const ViewResult& v : result.views) {
    nlohmann::ordered_json entry;
    entry["pose"] = v.pose_id;
    entry["camera"] = v.camera;
    entry["points"] = v.num_points;
    entry["used"] = v.used;
    if (!v.used) entry["rejected_because"] = v.rejected_because;
    entry["rms_px"] = v.rms_px;
    entry["max_px"] = v.max_px;
    entry["outlier"] = v.outlier;
    if (v.flipped) entry["flipped"] = true;
    views.push_back(entry);
  }
  root["views"] = views;
  AddWarningsJson(result.warnings, &root);
  root["notes"] = result.notes;
  root["options"] = OptionsJson(result.options);
  root["provenance"] = {{"handeye_version", result.handeye_version}, {"input", result.input}};
  return DumpJson(root);
}

void SaveResult(const CalibrationResult& result, const std::string& path) {
  WriteFileAtomically(path, ResultJson(result));
}

CalibrationResult LoadResult(const std::string& path) {
  const nlohmann::json json = ReadJsonFile(path);
  const JsonReader root(&json, path);
  root.ExpectObject("a handeye-result/1 object");
  const std::string format = root.Key("format").String();
  if (format != "handeye-result/1")
    throw root.Key("format").Error("\"handeye-result/1\", got \"" + format + "\"");
  CalibrationResult result;
  const std::string setup = root.Key("setup").String();
  const auto parsed_setup = ParseSetup(setup);
  if (!parsed_setup) throw root.Key("setup").Error("\"eye_to_hand\" or \"eye_in_hand\"");
  result.setup = *parsed_setup;
  const SetupFrames frames = FramesOf(result.setup);
  const std::string method = root.Key("method").String();
  const auto parsed_method = ParseMethod(method);
  if (!parsed_method) throw root.Key("method").Error("a method name, got \"" + method + "\"");
  result.method = *parsed_method;
  for (const auto& [name, cam] : root.Key("cameras").Members("an object of cameras by name")) {
    CameraResult c;
    c.name = name;
    c.calibrated = ReadBool(cam.Key("calibrated"));
    if (c.calibrated) {
      c.T_cam = cam.Key(frames.camera_key).Rigid(false);
      c.rms_px = cam.Key("rms_px").Number();
      if (cam.Has(frames.target_key)) c.own_T_target = cam.Key(frames.target_key).Rigid(false);
      if (cam.Has("intrinsics")) c.intrinsics = ReadIntrinsicsResult(cam, name);
      if (cam.Has("sigma")) c.sigma = ReadSigma(cam.Key("sigma"));
      if (cam.Has("given_intrinsics_offset_px")) {
        const JsonReader d = cam.Key("given_intrinsics_offset_px");
        c.given_intrinsics_offset_px = Eigen::Vector4d(d.Key("fx").Number(), d.Key("fy").Number(),
                                                       d.Key("cx").Number(), d.Key("cy").Number());
      }
      if (cam.Has("cross_validation")) {
        const JsonReader cv = cam.Key("cross_validation");
        CameraResult::CrossValidation v;
        v.folds = cv.Key("folds").Int(0);
        v.held_out_rms_px = cv.Key("held_out_rms_px").Number();
        v.position_spread_mm = cv.Key("position_spread_mm").Number();
        v.rotation_spread_deg = cv.Key("rotation_spread_deg").Number();
        c.cross_validation = v;
      }
      ReadDiagnostics(cam, &c);
    }
    c.views = cam.Key("views").Int(0);
    c.views_rejected = cam.Key("views_rejected").Int(0);
    result.cameras.push_back(c);
  }
  result.T_target = root.Key(frames.target_key).Rigid(false);
  const std::string target_sigma = frames.target_key + "_sigma";
  if (root.Has(target_sigma)) result.target_sigma = ReadSigma(root.Key(target_sigma));
  if (root.Has("camera_pairs")) {
    for (const auto& [key, entry] : root.Key("camera_pairs").Members("an object of camera pairs")) {
      const auto slash = key.find('/');
      if (slash == std::string::npos) throw entry.Error("a key of the form \"camK/camT\"");
      CameraPairResult p;
      p.camera_k = key.substr(0, slash);
      p.camera_t = key.substr(slash + 1);
      p.T_camk_camt = entry.Key("T_" + p.camera_k + "_" + p.camera_t).Rigid(false);
      p.shared_views = entry.Key("shared_views").Int(0);
      result.camera_pairs.push_back(p);
    }
  }
  const JsonReader metrics = root.Key("metrics");
  result.metrics.rms_px = metrics.Key("rms_px").Number();
  result.metrics.axzb_translation_mm = metrics.Key("axzb_translation_mm").Number();
  result.metrics.axzb_rotation_deg = metrics.Key("axzb_rotation_deg").Number();
  if (metrics.Has("axzb_camera_translation_mm"))
    result.metrics.axzb_camera_translation_mm = metrics.Key("axzb_camera_translation_mm").Number();
  const JsonReader solver = root.Key("solver");
  result.solver.seconds = solver.Key("seconds").Number();
  result.solver.iterations = solver.Key("iterations").Int(0);
  result.solver.converged = ReadBool(solver.Key("converged"));
  result.solver.termination = solver.Key("termination").String();
  if (solver.Has("cauchy_scale_px")) result.solver.cauchy_scale_px = solver.Key("cauchy_scale_px").Number();
  if (solver.Has("rounds")) result.solver.rounds = solver.Key("rounds").Int(0);
  if (solver.Has("robot_sigma_mm")) result.solver.robot_sigma_mm = solver.Key("robot_sigma_mm").Number();
  if (solver.Has("robot_sigma_deg")) result.solver.robot_sigma_deg = solver.Key("robot_sigma_deg").Number();
  if (solver.Has("robot_sigma_solved_mm"))  // results written before it: 0, the prior's is taken
    result.solver.robot_sigma_solved_mm = solver.Key("robot_sigma_solved_mm").Number();
  if (solver.Has("robot_sigma_solved_deg"))
    result.solver.robot_sigma_solved_deg = solver.Key("robot_sigma_solved_deg").Number();
  if (solver.Has("model")) {
    const JsonReader model = solver.Key("model");
    ModelChoice choice;
    choice.chosen = model.Key("chosen").String();
    choice.folds = model.Key("folds").Int(1);
    const JsonReader candidates = model.Key("candidates");
    const size_t n = candidates.ArraySize("an array of the robot models compared");
    for (size_t i = 0; i < n; ++i) {
      const JsonReader m = candidates.At(i);
      ModelCandidate candidate{m.Key("name").String(), m.Key("held_out_rms_px").Number(),
                               m.Key("points").Int(0)};
      if (m.Has("robot_sigma_mm")) candidate.robot_sigma_mm = m.Key("robot_sigma_mm").Number();
      if (m.Has("robot_sigma_deg")) candidate.robot_sigma_deg = m.Key("robot_sigma_deg").Number();
      choice.candidates.push_back(candidate);
    }
    result.solver.model = choice;
  }
  if (root.Has("views")) {
    const JsonReader views = root.Key("views");
    const size_t n = views.ArraySize("an array of views");
    for (size_t i = 0; i < n; ++i) {
      const JsonReader v = views.At(i);
      ViewResult vr;
      vr.pose_id = v.Key("pose").String();
      vr.camera = v.Key("camera").String();
      vr.num_points = v.Key("points").Int(0);
      vr.used = ReadBool(v.Key("used"));
      if (v.Has("rejected_because")) vr.rejected_because = v.Key("rejected_because").String();
      vr.rms_px = v.Key("rms_px").Number();
      vr.max_px = v.Key("max_px").Number();
      vr.outlier = ReadBool(v.Key("outlier"));
      if (v.Has("flipped")) vr.flipped = ReadBool(v.Key("flipped"));
      result.views.push_back(vr);
    }
  }
  result.warnings = ReadWarningsJson(root);
  if (root.Has("notes")) {
    const JsonReader notes = root.Key("notes");
    const size_t n = notes.ArraySize("an array of strings");
    for (size_t i = 0; i < n; ++i) result.notes.push_back(notes.At(i).String());
  }
  result.options.method = result.method;
  if (root.Has("options")) ReadOptions(root.Key("options"), &result.options);
  if (root.Has("provenance")) {
    const JsonReader provenance = root.Key("provenance");
    result.handeye_version = provenance.Key("handeye_version").String();
    result.input = provenance.Key("input").String();
  }
  return result;
}

}  // namespace handeye
