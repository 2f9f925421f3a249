// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/dataset_json.h"

#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "dataset_json_internal.h"
#include "handeye/core/error.h"
#include "handeye/core/input_limits.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/atomic_file.h"
#include "handeye/io/intrinsics_files.h"
#include "handeye/io/json_util.h"
#include "handeye/io/pose_formats.h"

namespace handeye {
namespace {

namespace fs = std::filesystem;
using OrderedJson = nlohmann::ordered_json;

using internal::kDatasetFormat;
using internal::kObservationsFormat;
using internal::PixelsJson;
using internal::ReadGroundTruth;
using internal::ReadIdsAndPixels;
using internal::ReadSetup;

// --- Reading -------------------------------------------------------------------

// A detected point lies in its image. One far outside (a corrupt or
// hand-edited file) is the observation's fault; left to the solve, it would
// be blamed on the robot record of its pose. The margin (10 % of the image)
// leaves room for points from another detector's pixel convention or a lens
// model that maps them a little past the edge.
void CheckPixelsInImage(const JsonReader& px_json, const Camera& camera, const Observation& view) {
  if (camera.width <= 0 || camera.height <= 0) return;
  const double margin_u = 0.1 * camera.width, margin_v = 0.1 * camera.height;
  for (std::size_t i = 0; i < view.points_px.size(); ++i) {
    const Eigen::Vector2d& px = view.points_px[i];
    if (px.x() >= -0.5 - margin_u && px.x() <= camera.width - 0.5 + margin_u &&
        px.y() >= -0.5 - margin_v && px.y() <= camera.height - 0.5 + margin_v)
      continue;
    std::ostringstream why;
    why.precision(6);
    why << "expected a pixel in the " << camera.width << " x " << camera.height
        << " image of camera '" << camera.name << "' (a detected point lies in it), got ("
        << px.x() << ", " << px.y() << "): this observation is wrong, not the robot pose";
    throw px_json.At(i).Error(why.str());
  }
}

std::shared_ptr<const Target> ReadTarget(const JsonReader& r) {
  const TargetSpec spec = TargetSpecFromJson(r);
  try {
    return MakeTarget(spec);
  } catch (const InputError& e) {
    // Plugins report paths inside the target object and do not know the file.
    throw e.WithFile(r.file(), r.path());
  }
}

std::vector<double> ReadDistortion(const JsonReader& r) {
  r.ExpectObject(
      "{\"model\": \"none\"} or {\"model\": \"opencv\", \"coeffs\": [k1, k2, p1, p2, ...]}");
  r.RejectUnknownKeys({"model", "coeffs"});
  const JsonReader model_json = r.Key("model");
  const std::string model = model_json.NonEmptyString("a distortion model, \"none\" or \"opencv\"");
  const JsonReader coeffs = r.Key("coeffs");
  if (model == "none") {
    if (coeffs.present() && coeffs.ArraySize("no coefficients") != 0)
      throw coeffs.Error("expected no coefficients for model \"none\" (use model \"opencv\")");
    return {};
  }
  if (model != "opencv")
    throw model_json.Error("unknown distortion model '" + model +
                           "'; expected \"none\" or \"opencv\"");
  const std::string expected =
      "4, 5, 8, 12 or 14 coefficients in OpenCV's order (k1, k2, p1, p2, k3, k4, k5, k6, ...)";
  const std::size_t n = coeffs.ArraySize(expected);
  if (n != 4 && n != 5 && n != 8 && n != 12 && n != 14)
    throw coeffs.Error("expected " + expected + ", got " + std::to_string(n));
  return coeffs.Numbers();
}

std::string ResolvePath(const std::string& file, const std::string& relative) {
  const fs::path p(relative);
  if (p.is_absolute()) return p.lexically_normal().string();
  return (fs::path(file).parent_path() / p).lexically_normal().string();
}

// `intrinsics_file` (io/intrinsics_files.h): {"path", "format", "camera" for kalibr}.
FileIntrinsics ReadCameraIntrinsicsFile(const JsonReader& r) {
  r.ExpectObject(
      "{\"path\": \"...\", \"format\": \"opencv\" | \"ros\" | \"kalibr\"} (kalibr also "
      "\"camera\": \"cam0\")");
  r.RejectUnknownKeys({"path", "format", "camera"});
  const std::string path = ResolvePath(r.file(), r.Key("path").NonEmptyString("the intrinsics file's path"));
  const JsonReader format_json = r.Key("format");
  const std::string format_name = format_json.NonEmptyString("\"opencv\", \"ros\" or \"kalibr\"");
  const auto format = ParseIntrinsicsFileFormat(format_name);
  if (!format)
    throw format_json.Error("unknown intrinsics file format '" + format_name +
                            "'; expected \"opencv\" (FileStorage), \"ros\" (camera_info) or \"kalibr\" "
                            "(camchain)");
  const JsonReader camera_json = r.Key("camera");
  std::string camera;
  if (*format == IntrinsicsFileFormat::kKalibr) {
    camera = camera_json.NonEmptyString("the camera's name in the camchain (e.g. \"cam0\")");
  } else if (camera_json.present()) {
    throw camera_json.Error("\"camera\" picks a camera of a Kalibr camchain; a " + format_name +
                            " file holds one camera");
  }
  try {
    return ReadIntrinsicsFile(path, *format, camera);
  } catch (const InputError& e) {
    // Say where the file was referenced from, so a wrong path is found fast.
    throw InputError(e.file(), e.json_path(),
                     e.expected() + " (intrinsics_file of " + r.file() + " at " + r.path() + ")");
  }
}

Camera ReadCamera(const JsonReader& r) {
  r.ExpectObject("a camera object with name, image_size, and intrinsics and distortion or intrinsics_file");
  r.RejectUnknownKeys({"name", "image_size", "intrinsics", "distortion", "intrinsics_file"});
  const JsonReader name_json = r.Key("name");
  const std::string name = name_json.NonEmptyString("a camera name");
  if (name.find('/') != std::string::npos)
    throw name_json.Error(
        "expected a camera name without '/' (it separates the names of a "
        "camera pair), got \"" +
        name + "\"");
  const JsonReader file_json = r.Key("intrinsics_file");
  std::optional<FileIntrinsics> from_file;
  if (file_json.present()) {
    for (const char* key : {"intrinsics", "distortion"})
      if (r.Has(key))
        throw r.Key(key).Error(std::string("give either intrinsics and distortion, or intrinsics_file; found both ") +
                               key + " and intrinsics_file");
    from_file = ReadCameraIntrinsicsFile(file_json);
  }
  const JsonReader size = r.Key("image_size");
  const std::string size_expected = "[width, height] in pixels";
  int width = 0, height = 0;
  if (size.present() || !from_file || !from_file->image_size) {
    if (size.ArraySize(size_expected) != 2)
      throw size.Error("expected " + size_expected + ", two positive integers");
    width = size.At(0).Int(1, 1 << 20);
    height = size.At(1).Int(1, 1 << 20);
  }
  if (from_file && from_file->image_size) {
    const auto [file_width, file_height] = *from_file->image_size;
    if (size.present() && (file_width != width || file_height != height))
      throw size.Error("image_size [" + std::to_string(width) + ", " + std::to_string(height) +
                       "] differs from the intrinsics file's [" + std::to_string(file_width) + ", " +
                       std::to_string(file_height) + "]");
    width = file_width;
    height = file_height;
  }
  // Checked here, before detect decodes a single image of this size.
  const JsonReader size_source = size.present() ? size : r.Key("intrinsics_file");
  RequireImagePixelsWithinLimit(width, height, size_source.file(), size_source.path());
  if (from_file) {
    std::string why;
    const auto camera = Camera::Make(name, width, height, from_file->fx, from_file->fy, from_file->cx, from_file->cy,
                                     from_file->distortion, &why);
    if (!camera) throw r.Error("expected " + why);
    return *camera;
  }
  if (!r.Has("intrinsics") && !r.Has("distortion")) {
    // No intrinsics: Calibrate() estimates them from the views (SPEC §4).
    std::string why;
    const double f = std::max(width, height);
    auto camera = Camera::Make(name, width, height, f, f, (width - 1) / 2.0, (height - 1) / 2.0, {}, &why);
    if (!camera) throw r.Error("expected " + why);
    camera->has_intrinsics = false;
    return *camera;
  }
  return ReadIntrinsicsJson(r, name, width, height);
}

}  // namespace

Camera ReadIntrinsicsJson(const JsonReader& r, const std::string& name, int width, int height) {
  const JsonReader intrinsics = r.Key("intrinsics");
  intrinsics.ExpectObject("{\"fx\", \"fy\", \"cx\", \"cy\"} in pixels (or intrinsics_file)");
  intrinsics.RejectUnknownKeys({"fx", "fy", "cx", "cy"});
  const double fx = intrinsics.Key("fx").Positive();
  const double fy = intrinsics.Key("fy").Positive();
  const double cx = intrinsics.Key("cx").Number();
  const double cy = intrinsics.Key("cy").Number();
  const std::vector<double> distortion = ReadDistortion(r.Key("distortion"));
  std::string why;
  const auto camera = Camera::Make(name, width, height, fx, fy, cx, cy, distortion, &why);
  if (!camera) throw r.Error("expected " + why);
  return *camera;
}

namespace {

std::string CameraList(const Dataset& dataset) {
  std::string list;
  for (const auto& c : dataset.cameras) list += (list.empty() ? "" : ", ") + c.name;
  return list;
}

void ReadCameras(const JsonReader& r, Dataset* dataset) {
  const std::size_t n = r.ArraySize("an array of camera objects");
  if (n == 0) throw r.Error("expected at least one camera");
  std::map<std::string, std::string> path_of_name;
  for (std::size_t i = 0; i < n; ++i) {
    const JsonReader entry = r.At(i);
    Camera camera = ReadCamera(entry);
    const auto [it, inserted] = path_of_name.emplace(camera.name, entry.path());
    if (!inserted)
      throw entry.Key("name").Error("duplicate camera name '" + camera.name + "' (also at " +
                                    it->second + ")");
    dataset->cameras.push_back(std::move(camera));
  }
}

// Millimetres written as metres put the flange a kilometre from the base,
// and the solve then failed in Ceres's words ("Residual and Jacobian
// evaluation failed"); the unit is named here instead.
void RequirePlausibleReach(const JsonReader& poses, const Dataset& dataset) {
  std::vector<Eigen::Vector3d> translations;
  for (const RobotPose& pose : dataset.poses) translations.push_back(pose.T_base_ee.translation());
  const auto farthest = ImplausibleReach(translations);
  if (!farthest || translations[*farthest].norm() <= kMaxRobotReachM) return;
  char distance[32];
  std::snprintf(distance, sizeof distance, "%.4g", translations[*farthest].norm());
  throw poses.At(*farthest).Key("T_base_ee").Error(
      std::string("expected a translation in metres; this one puts the flange ") + distance +
      " m from the robot base, farther than a robot reaches (10 m): millimetres written as metres? Write them "
      "as {\"translation_mm\": [x, y, z], ...} or divide by 1000");
}

void ReadPoses(const JsonReader& r, bool with_images, const LoadOptions& options,
               Dataset* dataset) {
  const std::size_t n = r.ArraySize("an array of robot pose objects");
  if (n == 0) throw r.Error("expected at least one robot pose");
  std::map<std::string, std::string> path_of_id;
  for (std::size_t i = 0; i < n; ++i) {
    const JsonReader entry = r.At(i);
    if (with_images) {
      entry.ExpectObject("a pose object with id, T_base_ee and images");
      entry.RejectUnknownKeys({"id", "T_base_ee", "images"});
    } else {
      entry.ExpectObject("a pose object with id and T_base_ee");
      entry.RejectUnknownKeys({"id", "T_base_ee"});
    }
    RobotPose pose;
    const JsonReader id = entry.Key("id");
    pose.id = id.NonEmptyString("a pose id");
    const auto [it, inserted] = path_of_id.emplace(pose.id, entry.path());
    if (!inserted)
      throw id.Error("duplicate pose id '" + pose.id + "' (also at " + it->second + ")");
    pose.T_base_ee = ReadPose(entry.Key("T_base_ee"), options.reorthonormalise);
    if (with_images) {
      for (const auto& [camera, image] :
           entry.Key("images").Members("an object {camera name: image path}")) {
        if (dataset->CameraIndex(camera) < 0)
          throw image.Error("unknown camera '" + camera +
                            "'; the cameras are: " + CameraList(*dataset));
        pose.images[camera] = ResolvePath(r.file(), image.NonEmptyString("an image path"));
      }
    }
    dataset->poses.push_back(std::move(pose));
  }
  RequirePlausibleReach(r, *dataset);
}

void ReadObservations(const JsonReader& r, Dataset* dataset) {
  const std::size_t n = r.ArraySize("an array of observation objects");
  std::map<std::pair<std::string, std::string>, std::string> path_of_view;
  for (std::size_t i = 0; i < n; ++i) {
    const JsonReader entry = r.At(i);
    entry.ExpectObject("an observation object with pose, camera, ids and points_px");
    entry.RejectUnknownKeys({"pose", "camera", "ids", "points_px"});
    Observation view;
    const JsonReader pose = entry.Key("pose");
    view.pose_id = pose.NonEmptyString("a pose id");
    if (dataset->PoseIndex(view.pose_id) < 0)
      throw pose.Error("unknown pose '" + view.pose_id +
                       "'; expected the id of an entry of /poses");
    const JsonReader camera = entry.Key("camera");
    view.camera = camera.NonEmptyString("a camera name");
    if (dataset->CameraIndex(view.camera) < 0)
      throw camera.Error("unknown camera '" + view.camera +
                         "'; the cameras are: " + CameraList(*dataset));
    const auto [it, inserted] =
        path_of_view.emplace(std::make_pair(view.pose_id, view.camera), entry.path());
    if (!inserted)
      throw entry.Error("duplicate observation of pose '" + view.pose_id + "' by camera '" +
                        view.camera + "' (also at " + it->second + ")");
    const JsonReader ids = entry.Key("ids");
    ReadIdsAndPixels(ids, entry.Key("points_px"), dataset->target.get(), &view);
    CheckPixelsInImage(entry.Key("points_px"), dataset->cameras[dataset->CameraIndex(view.camera)],
                       view);
    if (view.ids.empty())
      throw ids.Error(
          "expected at least one id (a view where the target was not found has no "
          "entry)");
    dataset->observations.push_back(std::move(view));
  }
}

std::string UnsupportedFormat(const std::string& format) {
  return "unsupported format '" + format + "'; expected \"" + kDatasetFormat + "\" or \"" +
         kObservationsFormat + "\"";
}

// --- Writing -------------------------------------------------------------------

OrderedJson CameraJson(const Camera& camera) {
  OrderedJson j = OrderedJson::object();
  j["name"] = camera.name;
  j["image_size"] = {camera.width, camera.height};
  if (camera.has_intrinsics) WriteIntrinsicsJson(camera, &j);
  return j;
}

OrderedJson Header(const Dataset& dataset, const char* format) {
  if (!dataset.target) throw std::invalid_argument("cannot save a dataset without a target");
  OrderedJson j = OrderedJson::object();
  j["format"] = format;
  j["setup"] = SetupName(dataset.setup);
  j["target"] = JsonFromTargetSpec(dataset.target->Spec());
  OrderedJson cameras = OrderedJson::array();
  for (const auto& camera : dataset.cameras) cameras.push_back(CameraJson(camera));
  j["cameras"] = cameras;
  return j;
}

// Images are written relative to the file's folder so the folder can move.
std::string RelativeImagePath(const std::string& image, const std::string& file) {
  const fs::path folder = fs::absolute(fs::path(file)).parent_path().lexically_normal();
  const fs::path absolute = fs::absolute(fs::path(image)).lexically_normal();
  const fs::path relative = absolute.lexically_relative(folder);
  return relative.empty() ? absolute.generic_string() : relative.generic_string();
}


}  // namespace

Dataset LoadDataset(const std::string& path, const LoadOptions& options,
                    std::vector<Warning>* warnings) {
  const nlohmann::json doc = ReadJsonFile(path);
  return DatasetFromJson(doc, path, options, warnings);
}

Dataset DatasetFromJson(const nlohmann::json& doc, const std::string& path, const LoadOptions& options,
                        std::vector<Warning>* warnings) {
  const JsonReader root(&doc, path);
  root.ExpectObject(std::string("a ") + kDatasetFormat + " or " + kObservationsFormat + " object");
  const JsonReader format_json = root.Key("format");
  const std::string format = format_json.NonEmptyString(std::string("\"") + kDatasetFormat +
                                                        "\" or \"" + kObservationsFormat + "\"");
  if (format != kDatasetFormat && format != kObservationsFormat)
    throw format_json.Error(UnsupportedFormat(format));
  const bool observations = format == kObservationsFormat;
  if (observations) {
    root.RejectUnknownKeys(
        {"format", "setup", "target", "cameras", "poses", "observations", "ground_truth"});
  } else {
    root.RejectUnknownKeys({"format", "setup", "target", "cameras", "poses", "ground_truth"});
  }

  Dataset dataset;
  dataset.setup = ReadSetup(root.Key("setup"));
  dataset.target = ReadTarget(root.Key("target"));
  if (warnings) {
    for (const auto& w : dataset.target->Warnings())
      warnings->push_back(GeneralWarning(WarningKind::kTargetAmbiguous, path + ": " + w));
  }
  ReadCameras(root.Key("cameras"), &dataset);
  ReadPoses(root.Key("poses"), !observations, options, &dataset);
  if (observations) ReadObservations(root.Key("observations"), &dataset);
  // Only `handeye evaluate` uses it, but a broken one should not wait until then.
  if (root.Has("ground_truth")) ReadGroundTruth(root.Key("ground_truth"), dataset.setup);
  return dataset;
}

void WriteIntrinsicsJson(const Camera& camera, nlohmann::ordered_json* j) {
  OrderedJson intrinsics = OrderedJson::object();
  intrinsics["fx"] = camera.fx();
  intrinsics["fy"] = camera.fy();
  intrinsics["cx"] = camera.cx();
  intrinsics["cy"] = camera.cy();
  (*j)["intrinsics"] = intrinsics;
  OrderedJson distortion = OrderedJson::object();
  if (camera.num_distortion == 0) {
    distortion["model"] = "none";
  } else {
    distortion["model"] = "opencv";
    distortion["coeffs"] = camera.Distortion();
  }
  (*j)["distortion"] = distortion;
}

void SaveDataset(const Dataset& dataset, const std::string& path) {
  OrderedJson j = Header(dataset, kDatasetFormat);
  OrderedJson poses = OrderedJson::array();
  for (const auto& pose : dataset.poses) {
    OrderedJson p = OrderedJson::object();
    p["id"] = pose.id;
    p["T_base_ee"] = JsonFromTransform(pose.T_base_ee);
    // A file LoadDataset would reject is never written.
    for (const auto& [camera, image] : pose.images)
      if (dataset.CameraIndex(camera) < 0)
        throw std::invalid_argument("SaveDataset: pose '" + pose.id + "' has an image of camera '" +
                                    camera + "', which the dataset does not have");
    OrderedJson images = OrderedJson::object();
    // Camera order, not name order, so the file lists views as the dataset does.
    for (const auto& camera : dataset.cameras) {
      auto it = pose.images.find(camera.name);
      if (it != pose.images.end()) images[camera.name] = RelativeImagePath(it->second, path);
    }
    p["images"] = images;
    poses.push_back(p);
  }
  j["poses"] = poses;
  WriteFileAtomically(path, DumpJson(j));
}

void SaveObservations(const Dataset& dataset, const std::string& path) {
  OrderedJson j = Header(dataset, kObservationsFormat);
  OrderedJson poses = OrderedJson::array();
  for (const auto& pose : dataset.poses) {
    OrderedJson p = OrderedJson::object();
    p["id"] = pose.id;
    p["T_base_ee"] = JsonFromTransform(pose.T_base_ee);
    poses.push_back(p);
  }
  j["poses"] = poses;
  OrderedJson views = OrderedJson::array();
  for (const auto& view : dataset.observations) {
    OrderedJson v = OrderedJson::object();
    v["pose"] = view.pose_id;
    v["camera"] = view.camera;
    v["ids"] = view.ids;
    v["points_px"] = PixelsJson(view.points_px);
    views.push_back(v);
  }
  j["observations"] = views;
  WriteFileAtomically(path, DumpJson(j));
}

}  // namespace handeye
