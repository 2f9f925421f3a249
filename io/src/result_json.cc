// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/result_json.h"
#include "handeye/io/dataset_json.h"

#include <algorithm>
#include <cmath>

#include "handeye/io/atomic_file.h"
#include "handeye/io/json_util.h"

namespace handeye {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

const char* CameraKey(Setup setup) { return setup == Setup::kEyeToHand ? "T_base_cam" : "T_ee_cam"; }
const char* TargetKey(Setup setup) { return setup == Setup::kEyeToHand ? "T_ee_target" : "T_base_target"; }

// Summaries for people: millimetres, fixed-axis roll/pitch/yaw (x, y, z; R =
// Rz(yaw)·Ry(pitch)·Rx(roll)) in degrees, and the quaternion.
void AddSummary(const Eigen::Isometry3d& T, nlohmann::ordered_json* out) {
  const Eigen::Vector3d t = 1000.0 * T.translation();
  const Eigen::Matrix3d R = T.rotation();
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double roll = std::atan2(R(2, 1), R(2, 2));
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  Eigen::Quaterniond q(R);
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  (*out)["translation_mm"] = {t.x(), t.y(), t.z()};
  (*out)["rpy_deg"] = {roll * kRadToDeg, pitch * kRadToDeg, yaw * kRadToDeg};
  (*out)["quaternion_xyzw"] = {q.x(), q.y(), q.z(), q.w()};
}

bool ReadBool(const JsonReader& value) {
  if (!value.present() || !value.json().is_boolean()) throw value.Error("true or false");
  return value.json().get<bool>();
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

}  // namespace

void SaveResult(const CalibrationResult& result, const std::string& path) {
  nlohmann::ordered_json root;
  root["format"] = "handeye-result/1";
  root["setup"] = SetupName(result.setup);
  root["method"] = MethodName(result.method);
  nlohmann::ordered_json cameras = nlohmann::ordered_json::object();
  for (const CameraResult& cam : result.cameras) {
    nlohmann::ordered_json c;
    c["calibrated"] = cam.calibrated;
    if (cam.calibrated) {
      c[CameraKey(result.setup)] = JsonFromTransform(cam.T_cam);
      AddSummary(cam.T_cam, &c);
      if (cam.own_T_target) c[TargetKey(result.setup)] = JsonFromTransform(*cam.own_T_target);
      c["rms_px"] = cam.rms_px;
      if (cam.intrinsics) AddIntrinsics(*cam.intrinsics, &c);
    }
    c["views"] = cam.views;
    c["views_rejected"] = cam.views_rejected;
    cameras[cam.name] = c;
  }
  root["cameras"] = cameras;
  root[TargetKey(result.setup)] = JsonFromTransform(result.T_target);
  nlohmann::ordered_json target_summary;
  AddSummary(result.T_target, &target_summary);
  root[std::string(TargetKey(result.setup)) + "_summary"] = target_summary;
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
                     {"axzb_rotation_deg", result.metrics.axzb_rotation_deg}};
  root["solver"] = {{"seconds", result.solver.seconds},
                    {"iterations", result.solver.iterations},
                    {"converged", result.solver.converged},
                    {"termination", result.solver.termination},
                    {"cauchy_scale_px", result.solver.cauchy_scale_px},
                    {"rounds", result.solver.rounds},
                    {"robot_sigma_mm", result.solver.robot_sigma_mm},
                    {"robot_sigma_deg", result.solver.robot_sigma_deg}};
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
    views.push_back(entry);
  }
  root["views"] = views;
  root["warnings"] = result.warnings;
  root["notes"] = result.notes;
  WriteFileAtomically(path, DumpJson(root));
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
  const std::string method = root.Key("method").String();
  const auto parsed_method = ParseMethod(method);
  if (!parsed_method) throw root.Key("method").Error("a method name, got \"" + method + "\"");
  result.method = *parsed_method;
  for (const auto& [name, cam] : root.Key("cameras").Members("an object of cameras by name")) {
    CameraResult c;
    c.name = name;
    c.calibrated = ReadBool(cam.Key("calibrated"));
    if (c.calibrated) {
      c.T_cam = cam.Key(CameraKey(result.setup)).Rigid(false);
      c.rms_px = cam.Key("rms_px").Number();
      if (cam.Has(TargetKey(result.setup))) c.own_T_target = cam.Key(TargetKey(result.setup)).Rigid(false);
      if (cam.Has("intrinsics")) c.intrinsics = ReadIntrinsicsResult(cam, name);
    }
    c.views = cam.Key("views").Int(0);
    c.views_rejected = cam.Key("views_rejected").Int(0);
    result.cameras.push_back(c);
  }
  result.T_target = root.Key(TargetKey(result.setup)).Rigid(false);
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
  const JsonReader solver = root.Key("solver");
  result.solver.seconds = solver.Key("seconds").Number();
  result.solver.iterations = solver.Key("iterations").Int(0);
  result.solver.converged = ReadBool(solver.Key("converged"));
  result.solver.termination = solver.Key("termination").String();
  if (solver.Has("cauchy_scale_px")) result.solver.cauchy_scale_px = solver.Key("cauchy_scale_px").Number();
  if (solver.Has("rounds")) result.solver.rounds = solver.Key("rounds").Int(0);
  if (solver.Has("robot_sigma_mm")) result.solver.robot_sigma_mm = solver.Key("robot_sigma_mm").Number();
  if (solver.Has("robot_sigma_deg")) result.solver.robot_sigma_deg = solver.Key("robot_sigma_deg").Number();
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
      result.views.push_back(vr);
    }
  }
  for (auto [key, list] : {std::make_pair("warnings", &result.warnings), std::make_pair("notes", &result.notes)}) {
    if (!root.Has(key)) continue;
    const JsonReader strings = root.Key(key);
    const size_t n = strings.ArraySize("an array of strings");
    for (size_t i = 0; i < n; ++i) list->push_back(strings.At(i).String());
  }
  return result;
}

}  // namespace handeye
