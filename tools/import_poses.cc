// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye import-poses POSES --template TEMPLATE.json -o DATASET.json`:
// makes a handeye-dataset/1 from a robot pose list (CSV with a quaternion,
// rotation vector or Euler angles, or a YAML list of ROS poses;
// io/pose_formats.h) and a template that holds everything else (setup,
// target, cameras), with image paths built from the pose ids.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/io/atomic_file.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/json_util.h"
#include "handeye/io/pose_formats.h"
#include "output_paths.h"

namespace handeye::tools {
namespace {

using OrderedJson = nlohmann::ordered_json;

struct ImportPosesArgs {
  std::string csv;
  std::string template_path;
  std::string output;
  std::string unit = "m";
  std::string rotation;  // "" = from the CSV header
  std::vector<std::string> images;  // CAM=PATTERN
  bool reorthonormalise = false;
};

constexpr char kIdPlaceholder[] = "{id}";

std::string Replace(std::string text, const std::string& what, const std::string& with) {
  for (std::size_t pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + with.size()))
    text.replace(pos, what.size(), with);
  return text;
}

// The template in its own key order (ReadJsonFile has checked it already:
// well-formed, no duplicate keys), so the output reads like the template.
OrderedJson ReadOrdered(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return OrderedJson::parse(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()));
}

// A path relative to `from_file`'s folder, made relative to `to_file`'s
// folder (absolute when no relative path exists, e.g. another drive).
std::string Rebase(const std::string& path, const std::string& from_file, const std::string& to_file) {
  namespace fs = std::filesystem;
  if (fs::path(path).is_absolute()) return path;
  const fs::path absolute = fs::absolute(fs::path(from_file).parent_path() / path).lexically_normal();
  const fs::path to_folder = fs::absolute(fs::path(to_file)).parent_path().lexically_normal();
  const fs::path relative = absolute.lexically_relative(to_folder);
  return relative.empty() ? absolute.generic_string() : relative.generic_string();
}

// An image path of --images, given relative to the current folder like every
// path on the command line, as the dataset stores it: relative to the
// output's folder.
std::string RebaseFromCurrentFolder(const std::string& path, const std::string& to_file) {
  return Rebase(path, (std::filesystem::current_path() / "-").string(), to_file);
}

// Every image --images names must exist: a typo in a pattern would otherwise
// show only when detect runs.
void RequireImagesExist(const std::vector<PoseRow>& rows, const std::map<std::string, std::string>& pattern_of_camera) {
  std::size_t missing = 0, total = 0;
  std::string first, first_what;
  for (const PoseRow& row : rows)
    for (const auto& [camera, pattern] : pattern_of_camera) {
      const std::string image = Replace(pattern, kIdPlaceholder, row.id);
      std::error_code ec;
      ++total;
      if (std::filesystem::is_regular_file(image, ec) || missing++ > 0) continue;
      first = image;
      first_what = "camera '" + camera + "', pose '" + row.id + "', from --images " + camera + "=" + pattern;
    }
  if (missing > 0)
    throw InputError(first, "", "image file does not exist (" + first_what + "; " + std::to_string(missing) + " of " +
                                    std::to_string(total) +
                                    " images are missing; --images paths are relative to the current folder)");
}

PoseListOptions ReadOptions(const ImportPosesArgs& args) {
  if (args.unit != "m" && args.unit != "mm")
    throw InputError("", "", "--translation-unit: expected m or mm, got '" + args.unit + "'");
  PoseListOptions options;
  options.unit = args.unit == "mm" ? LengthUnit::kMillimetre : LengthUnit::kMetre;
  options.reorthonormalise = args.reorthonormalise;
  if (!args.rotation.empty()) {
    options.rotation = ParseCsvRotation(args.rotation);
    if (!options.rotation)
      throw InputError("", "", "--rotation: expected quaternion, rotvec, kuka_abc or rpy, got '" + args.rotation + "'");
  }
  return options;
}

void RunImportPoses(const ImportPosesArgs& args) {
  const PoseListOptions options = ReadOptions(args);
  CheckFileOutputs({{"POSES", args.csv}, {"--template", args.template_path}},
                   {{"-o", args.output}});
  const std::vector<PoseRow> rows = ReadPoseList(args.csv, options);
  RequirePlausibleReach(rows, args.csv, options.unit, "--translation-unit");

  const nlohmann::json checked = ReadJsonFile(args.template_path);
  const JsonReader root(&checked, args.template_path);
  root.ExpectObject("a handeye-dataset/1 object without poses (the template)");
  const JsonReader format = root.Key("format");
  if (format.NonEmptyString("\"handeye-dataset/1\"") != "handeye-dataset/1")
    throw format.Error("expected \"handeye-dataset/1\" (a template for a dataset)");
  if (root.Has("poses"))
    throw root.Key("poses").Error("the template must not list poses; import-poses writes them from " + args.csv);
  // The template's own problems are reported against the template: check it
  // with one stand-in pose before adding the real ones.
  nlohmann::json probe = checked;
  nlohmann::json stand_in = nlohmann::json::object();
  stand_in["id"] = rows.front().id;
  stand_in["T_base_ee"] = nlohmann::json::parse(JsonFromTransform(Eigen::Isometry3d::Identity()).dump());
  stand_in["images"] = nlohmann::json::object();
  probe["poses"] = nlohmann::json::array({stand_in});
  std::vector<Warning> warnings;
  const Dataset dataset = DatasetFromJson(probe, args.template_path, {}, &warnings);
  PrintWarnings(warnings);

  std::map<std::string, std::string> pattern_of_camera;
  for (const std::string& spec : args.images) {
    const std::size_t eq = spec.find('=');
    const std::string camera = spec.substr(0, eq);
    const std::string pattern = eq == std::string::npos ? "" : spec.substr(eq + 1);
    if (eq == std::string::npos || camera.empty() || pattern.find(kIdPlaceholder) == std::string::npos)
      throw InputError("", "", "--images: expected CAMERA=PATTERN with {id} in the pattern (e.g. cam0=images/cam0/{id}.png), got '" +
                                   spec + "'");
    if (dataset.CameraIndex(camera) < 0) {
      std::string names;
      for (const auto& c : dataset.cameras) names += (names.empty() ? "" : ", ") + c.name;
      throw InputError("", "", "--images: unknown camera '" + camera + "'; the template's cameras are: " + names);
    }
    if (!pattern_of_camera.emplace(camera, pattern).second)
      throw InputError("", "", "--images: camera '" + camera + "' given twice");
  }
  RequireImagesExist(rows, pattern_of_camera);

  OrderedJson out = ReadOrdered(args.template_path);
  // Intrinsics files are referenced relative to the template; the dataset
  // may be written elsewhere.
  for (auto& camera : out["cameras"])
    if (camera.contains("intrinsics_file"))
      camera["intrinsics_file"]["path"] =
          Rebase(camera["intrinsics_file"]["path"].get<std::string>(), args.template_path, args.output);
  OrderedJson poses = OrderedJson::array();
  for (const PoseRow& row : rows) {
    OrderedJson pose = OrderedJson::object();
    pose["id"] = row.id;
    pose["T_base_ee"] = JsonFromTransform(row.T_base_ee);
    OrderedJson images = OrderedJson::object();
    // Camera order, as SaveDataset writes them.
    for (const auto& camera : dataset.cameras) {
      const auto it = pattern_of_camera.find(camera.name);
      if (it != pattern_of_camera.end())
        images[camera.name] = RebaseFromCurrentFolder(Replace(it->second, kIdPlaceholder, row.id), args.output);
    }
    pose["images"] = images;
    poses.push_back(pose);
  }
  out["poses"] = poses;
  // What is written must load: check the whole document where it will live
  // (image paths are relative to the output's folder).
  DatasetFromJson(nlohmann::json::parse(out.dump()), args.output);
  WriteFileAtomically(args.output, DumpJson(out));
  std::cerr << "wrote " << args.output << ": " << rows.size() << " poses from " << args.csv << ", images for "
            << pattern_of_camera.size() << " of " << dataset.cameras.size() << " cameras\n";
}

}  // namespace

void RegisterImportPoses(CLI::App& app) {
  auto args = std::make_shared<ImportPosesArgs>();
  CLI::App* cmd = app.add_subcommand(
      "import-poses", "make a dataset from a robot pose list (CSV or YAML, docs/formats.md) and a template");
  cmd->add_option("POSES", args->csv,
                  "T_base_ee per pose: CSV with header id,x,y,z then qx,qy,qz,qw | rx,ry,rz (rotation vector, "
                  "rad) | a,b,c (KUKA, deg) | roll,pitch,yaw (deg); or .yaml/.yml, a list of ROS "
                  "geometry_msgs/Pose")
      ->required();
  cmd->add_option("--template", args->template_path,
                  "handeye-dataset/1 file without poses: format, setup, target and cameras")
      ->required();
  cmd->add_option("-o,--output", args->output, "dataset file to write (handeye-dataset/1)")->required();
  cmd->add_option("--translation-unit", args->unit,
                  "unit of x, y, z: m (default) or mm; a pose over 10 m from the base, or all within 1 cm, "
                  "is refused as a unit mistake");
  cmd->add_option("--rotation", args->rotation,
                  "the CSV's rotation columns whatever the header calls them: quaternion, rotvec, kuka_abc or rpy");
  cmd->add_option("--images", args->images,
                  "CAMERA=PATTERN, image path per pose with {id} replaced by the pose id, relative to the "
                  "current folder (written relative to the output's folder); every file must exist (repeat "
                  "per camera)")
      ->allow_extra_args(false);  // one value per --images, so POSES after it stays positional
  cmd->add_flag("--reorthonormalise", args->reorthonormalise,
                "normalise quaternions that are not unit instead of rejecting them");
  cmd->callback([args]() { RunImportPoses(*args); });
}

HANDEYE_SUBCOMMAND(80, RegisterImportPoses);

}  // namespace handeye::tools
