// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye-cell/1` (io/plan_json.h): what is known about a cell before a capture.
#include <cmath>

#include "cell_json_internal.h"
#include "handeye/core/error.h"
#include "handeye/core/setup_frames.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/atomic_file.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/json_util.h"
#include "handeye/io/plan_json.h"
#include "handeye/io/pose_formats.h"

namespace handeye {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr char kCellFormat[] = "handeye-cell/1";

Eigen::Vector3d Vector3(const JsonReader& r) {
  const std::vector<double> v = r.Numbers(3);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

/// {"position_m", "rotation_deg"}: how far a rough pose may be off.
void ReadUncertainty(const JsonReader& r, double* position_m, double* rotation_rad) {
  r.ExpectObject("{\"position_m\": ..., \"rotation_deg\": ...}: how far the rough pose may be off");
  r.RejectUnknownKeys({"position_m", "rotation_deg"});
  *position_m = r.Key("position_m").Positive();
  *rotation_rad = r.Key("rotation_deg").Positive() * kDeg;
}

/// A camera's guess of intrinsics: given ones, or from its horizontal field of view.
Camera ReadPlanIntrinsics(const JsonReader& r, const std::string& name, int width, int height, bool* unknown) {
  *unknown = !r.Has("intrinsics");
  if (!*unknown) return ReadIntrinsicsJson(r, name, width, height);
  const JsonReader fov = r.Key("horizontal_fov_deg");
  if (!fov.present())
    throw r.Error("expected \"intrinsics\" (and \"distortion\"), or \"horizontal_fov_deg\" for a camera whose "
                  "intrinsics are unknown");
  const double degrees = fov.Positive();
  if (degrees >= 170) throw fov.Error("expected a field of view under 170 degrees");
  const double f = 0.5 * width / std::tan(0.5 * degrees * kDeg);
  std::string why;
  const auto camera = Camera::Make(name, width, height, f, f, (width - 1) / 2.0, (height - 1) / 2.0, {}, &why);
  if (!camera) throw fov.Error("expected a usable field of view: " + why);
  return *camera;
}

PlanCamera ReadPlanCamera(const JsonReader& r, const SetupFrames& frames) {
  r.ExpectObject("a camera object");
  r.RejectUnknownKeys({"name", "image_size", "intrinsics", "distortion", "horizontal_fov_deg",
                       "refine_intrinsics", frames.camera_key, "pose_uncertainty",
                       "pixel_sigma_px"});
  PlanCamera out;
  const std::string name = r.Key("name").NonEmptyString("a camera name");
  const JsonReader size = r.Key("image_size");
  if (size.ArraySize("[width, height]") != 2) throw size.Error("expected [width, height]");
  const int width = size.At(0).Int(1, 100000), height = size.At(1).Int(1, 100000);
  bool unknown = false;
  out.camera = ReadPlanIntrinsics(r, name, width, height, &unknown);
  out.refine_intrinsics = unknown || (r.Has("refine_intrinsics") && r.Key("refine_intrinsics").json().is_boolean() &&
                                      r.Key("refine_intrinsics").json().get<bool>());
  out.intrinsics_unknown = unknown;
  if (r.Has("refine_intrinsics") && !r.Key("refine_intrinsics").json().is_boolean())
    throw r.Key("refine_intrinsics").Error("expected true or false");
  out.T_mount_cam = ReadPose(r.Key(frames.camera_key), true);
  ReadUncertainty(r.Key("pose_uncertainty"), &out.position_sigma_m, &out.rotation_sigma_rad);
  if (r.Has("pixel_sigma_px")) out.pixel_sigma_px = r.Key("pixel_sigma_px").Positive();
  return out;
}

void ReadRegion(const JsonReader& r, PlanRegion* region) {
  r.ExpectObject("a region with \"box_m\" and/or \"taught_poses\", and optionally \"tilt\"");
  r.RejectUnknownKeys({"box_m", "taught_poses", "tilt"});
  if (r.Has("box_m")) {
    const JsonReader box = r.Key("box_m");
    box.ExpectObject("{\"min\": [x, y, z], \"max\": [x, y, z]} in metres, base frame");
    box.RejectUnknownKeys({"min", "max"});
    const Eigen::Vector3d min = Vector3(box.Key("min")), max = Vector3(box.Key("max"));
    if ((min.array() >= max.array()).any()) throw box.Error("expected min below max on every axis");
    region->box = Eigen::AlignedBox3d(min, max);
  }
  if (r.Has("taught_poses")) {
    const JsonReader taught = r.Key("taught_poses");
    for (std::size_t i = 0; i < taught.ArraySize("a list of {\"id\", \"T_base_ee\"}"); ++i)
      region->taught.push_back(ReadPose(taught.At(i).Key("T_base_ee"), true));
  }
  if (!region->box && region->taught.empty()) throw r.Error("expected \"box_m\", \"taught_poses\" or both");
  if (r.Has("tilt")) {
    const JsonReader tilt = r.Key("tilt");
    tilt.ExpectObject("{\"axis\": [x, y, z], \"max_deg\": D}: the tool's z axis within D degrees of axis");
    tilt.RejectUnknownKeys({"axis", "max_deg"});
    region->tilt_axis = Vector3(tilt.Key("axis"));
    if (!(region->tilt_axis.norm() > 0)) throw tilt.Key("axis").Error("expected a non-zero axis");
    region->tilt_axis.normalize();
    region->max_tilt_rad = tilt.Key("max_deg").Positive() * kDeg;
  }
}

void ReadOptional(const JsonReader& r, const char* key, double* value) {
  if (r.Has(key)) *value = r.Key(key).Number();
}

}  // namespace

namespace internal {

nlohmann::ordered_json NoiseJson(const PlanCell& cell) {
  return {{"pixel_sigma_px", cell.pixel_sigma_px},
          {"robot_sigma_mm", cell.robot_sigma_mm},
          {"robot_sigma_deg", cell.robot_sigma_deg},
          {"intrinsics_sigma", JsonFromIntrinsicsSigma(cell.intrinsics_sigma)}};
}

}  // namespace internal

PlanCell LoadPlanCell(const std::string& path) {
  const nlohmann::json json = ReadJsonFile(path);
  const JsonReader root(&json, path);
  root.ExpectObject("a handeye-cell/1 object");
  if (root.Key("format").String() != kCellFormat) throw root.Key("format").Error("expected \"handeye-cell/1\"");
  const auto setup = ParseSetup(root.Key("setup").String());
  if (!setup) throw root.Key("setup").Error("expected \"eye_to_hand\" or \"eye_in_hand\"");
  const SetupFrames frames = FramesOf(*setup);
  root.RejectUnknownKeys({"format", "setup", "target", "cameras", frames.target_key, "target_pose_uncertainty",
                          "noise", "region", "view"});
  PlanCell cell;
  cell.setup = *setup;
  try {
    cell.target = MakeTarget(TargetSpecFromJson(root.Key("target")));
  } catch (const InputError& e) {
    throw e.WithFile(path, "/target");
  }
  const JsonReader cameras = root.Key("cameras");
  for (std::size_t k = 0; k < cameras.ArraySize("a list of cameras"); ++k)
    cell.cameras.push_back(ReadPlanCamera(cameras.At(k), frames));
  cell.T_holder_target = ReadPose(root.Key(frames.target_key), true);
  ReadUncertainty(root.Key("target_pose_uncertainty"), &cell.target_position_sigma_m, &cell.target_rotation_sigma_rad);
  if (root.Has("noise")) {
    const JsonReader noise = root.Key("noise");
    noise.RejectUnknownKeys({"pixel_sigma_px", "robot_sigma_mm", "robot_sigma_deg", "intrinsics_sigma"});
    ReadOptional(noise, "pixel_sigma_px", &cell.pixel_sigma_px);
    ReadOptional(noise, "robot_sigma_mm", &cell.robot_sigma_mm);
    ReadOptional(noise, "robot_sigma_deg", &cell.robot_sigma_deg);
    if (noise.Has("intrinsics_sigma")) {
      const JsonReader given = noise.Key("intrinsics_sigma");
      given.RejectUnknownKeys({"focal_percent", "principal_point_px"});
      ReadOptional(given, "focal_percent", &cell.intrinsics_sigma.focal_percent);
      ReadOptional(given, "principal_point_px", &cell.intrinsics_sigma.principal_point_px);
    }
  }
  ReadRegion(root.Key("region"), &cell.region);
  if (root.Has("view")) {
    const JsonReader view = root.Key("view");
    view.RejectUnknownKeys({"margin_px", "max_view_angle_deg", "min_square_px"});
    ReadOptional(view, "margin_px", &cell.constraints.margin_px);
    ReadOptional(view, "max_view_angle_deg", &cell.constraints.max_view_angle_deg);
    ReadOptional(view, "min_square_px", &cell.constraints.min_square_px);
  }
  std::string why;
  if (!cell.Check(&why)) throw InputError(path, "", "expected " + why);
  return cell;
}

void SavePlanCell(const PlanCell& cell, const std::string& path) {
  const SetupFrames frames = FramesOf(cell.setup);
  nlohmann::ordered_json j;
  j["format"] = kCellFormat;
  j["setup"] = SetupName(cell.setup);
  j["target"] = JsonFromTargetSpec(cell.target->Spec());
  j["cameras"] = nlohmann::ordered_json::array();
  for (const PlanCamera& camera : cell.cameras) {
    nlohmann::ordered_json c;
    c["name"] = camera.camera.name;
    c["image_size"] = {camera.camera.width, camera.camera.height};
    if (camera.intrinsics_unknown)  // the guess ReadPlanIntrinsics makes of it
      c["horizontal_fov_deg"] =
          2.0 * std::atan(0.5 * camera.camera.width / camera.camera.fx()) / kDeg;
    else
      WriteIntrinsicsJson(camera.camera, &c);
    c["refine_intrinsics"] = camera.refine_intrinsics;
    c[frames.camera_key] = JsonFromTransform(camera.T_mount_cam);
    c["pose_uncertainty"] = {{"position_m", camera.position_sigma_m},
                             {"rotation_deg", camera.rotation_sigma_rad / kDeg}};
    if (camera.pixel_sigma_px > 0) c["pixel_sigma_px"] = camera.pixel_sigma_px;
    j["cameras"].push_back(c);
  }
  j[frames.target_key] = JsonFromTransform(cell.T_holder_target);
  j["target_pose_uncertainty"] = {{"position_m", cell.target_position_sigma_m},
                                  {"rotation_deg", cell.target_rotation_sigma_rad / kDeg}};
  j["noise"] = internal::NoiseJson(cell);
  nlohmann::ordered_json region;
  if (cell.region.box)
    region["box_m"] = {{"min", {cell.region.box->min().x(), cell.region.box->min().y(), cell.region.box->min().z()}},
                       {"max", {cell.region.box->max().x(), cell.region.box->max().y(), cell.region.box->max().z()}}};
  if (!cell.region.taught.empty()) {
    region["taught_poses"] = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < cell.region.taught.size(); ++i)
      region["taught_poses"].push_back({{"id", std::to_string(i + 1)},
                                        {"T_base_ee", JsonFromTransform(cell.region.taught[i])}});
  }
  if (cell.region.max_tilt_rad < M_PI)
    region["tilt"] = {{"axis", {cell.region.tilt_axis.x(), cell.region.tilt_axis.y(), cell.region.tilt_axis.z()}},
                      {"max_deg", cell.region.max_tilt_rad / kDeg}};
  j["region"] = region;
  j["view"] = {{"margin_px", cell.constraints.margin_px},
               {"max_view_angle_deg", cell.constraints.max_view_angle_deg},
               {"min_square_px", cell.constraints.min_square_px}};
  WriteFileAtomically(path, DumpJson(j));
}

}  // namespace handeye
