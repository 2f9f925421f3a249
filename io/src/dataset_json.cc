// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/dataset_json.h"

#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>

#include "handeye/core/error.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/atomic_file.h"
#include "handeye/io/intrinsics_files.h"
#include "handeye/io/json_util.h"
#include "handeye/io/pose_formats.h"

namespace handeye {
namespace {

namespace fs = std::filesystem;
using OrderedJson = nlohmann::ordered_json;

constexpr char kDatasetFormat[] = "handeye-dataset/1";
constexpr char kObservationsFormat[] = "handeye-observations/1";
constexpr char kGroundTruthFormat[] = "handeye-ground-truth/1";

// --- Reading -------------------------------------------------------------------

Setup ReadSetup(const JsonReader& r) {
  const std::string name = r.NonEmptyString("a setup, \"eye_to_hand\" or \"eye_in_hand\"");
  const auto setup = ParseSetup(name);
  if (!setup)
    throw r.Error("unknown setup '" + name + "'; expected \"eye_to_hand\" or \"eye_in_hand\"");
  return *setup;
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
}

// `ids` and pixels of one view; ids unique and >= 0. `target` (may be null)
// additionally requires every id to be one of its points.
void ReadIdsAndPixels(const JsonReader& ids_json, const JsonReader& px_json, const Target* target,
                      Observation* view) {
  view->ids = ids_json.Ints(0);
  std::map<int, std::size_t> index_of_id;
  for (std::size_t k = 0; k < view->ids.size(); ++k) {
    const int id = view->ids[k];
    const auto [it, inserted] = index_of_id.emplace(id, k);
    if (!inserted)
      throw ids_json.At(k).Error("duplicate id " + std::to_string(id) + " (also at " +
                                 ids_json.path() + "/" + std::to_string(it->second) + ")");
    if (target && !target->FindPoint(id)) {
      const auto& points = target->Points();
      throw ids_json.At(k).Error("id " + std::to_string(id) + " is not a point of the '" +
                                 target->Type() + "' target (its " + std::to_string(points.size()) +
                                 " points have ids " + std::to_string(points.front().id) + ".." +
                                 std::to_string(points.back().id) + ")");
    }
  }
  view->points_px = px_json.Points2();
  if (view->points_px.size() != view->ids.size())
    throw px_json.Error("expected " + std::to_string(view->ids.size()) +
                        " pixels [u, v], one per id, got " +
                        std::to_string(view->points_px.size()));
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
    if (view.ids.empty())
      throw ids.Error(
          "expected at least one id (a view where the target was not found has no "
          "entry)");
    dataset->observations.push_back(std::move(view));
  }
}

struct TruthKeys {
  const char* cam;
  const char* target;
};

TruthKeys KeysOf(Setup setup) {
  return setup == Setup::kEyeToHand ? TruthKeys{"T_base_cam", "T_ee_target"}
                                    : TruthKeys{"T_ee_cam", "T_base_target"};
}

// A ground-truth object: a whole handeye-ground-truth/1 file, or a dataset's
// `ground_truth` object (then `dataset_setup` is the dataset's and the object
// may leave out `format` and `setup`).
GroundTruth ReadGroundTruth(const JsonReader& r, std::optional<Setup> dataset_setup) {
  r.ExpectObject("a ground-truth object");
  GroundTruth truth;
  const JsonReader format = r.Key("format");
  if (format.present() || !dataset_setup) {
    const std::string name = format.NonEmptyString(std::string("\"") + kGroundTruthFormat + "\"");
    if (name != kGroundTruthFormat)
      throw format.Error("unsupported format '" + name + "'; expected \"" + kGroundTruthFormat +
                         "\"");
  }
  const JsonReader setup = r.Key("setup");
  if (setup.present() || !dataset_setup) {
    truth.setup = ReadSetup(setup);
    if (dataset_setup && truth.setup != *dataset_setup)
      throw setup.Error(std::string("expected the dataset's setup \"") + SetupName(*dataset_setup) +
                        "\"");
  } else {
    truth.setup = *dataset_setup;
  }
  const TruthKeys keys = KeysOf(truth.setup);
  const Setup other = truth.setup == Setup::kEyeToHand ? Setup::kEyeInHand : Setup::kEyeToHand;
  for (const char* key : {KeysOf(other).cam, KeysOf(other).target})
    if (r.Has(key))
      throw r.Key(key).Error(std::string(key) + " belongs to " + SetupName(other) +
                             " ground truth; for " + SetupName(truth.setup) + " expected " +
                             keys.cam + " and " + keys.target);
  r.RejectUnknownKeys({"format", "setup", keys.cam, keys.target, "poses"});

  const JsonReader cams = r.Key(keys.cam);
  for (const auto& [name, T] : cams.Members("an object {camera name: 4x4 transform}"))
    truth.T_cam[name] = T.Rigid(false);
  if (truth.T_cam.empty()) throw cams.Error("expected at least one camera");
  truth.has_T_target = r.Has(keys.target);
  if (truth.has_T_target) truth.T_target = r.Key(keys.target).Rigid(false);

  const JsonReader poses = r.Key("poses");
  if (!poses.present()) return truth;
  const std::size_t n = poses.ArraySize("an array of per-pose truths");
  std::map<std::string, std::string> path_of_id;
  for (std::size_t i = 0; i < n; ++i) {
    const JsonReader entry = poses.At(i);
    entry.ExpectObject("an object with id, T_base_ee_true and points_px");
    entry.RejectUnknownKeys({"id", "T_base_ee_true", "points_px"});
    GroundTruth::PoseTruth pose;
    const JsonReader id = entry.Key("id");
    pose.id = id.NonEmptyString("a pose id");
    const auto [it, inserted] = path_of_id.emplace(pose.id, entry.path());
    if (!inserted)
      throw id.Error("duplicate pose id '" + pose.id + "' (also at " + it->second + ")");
    pose.T_base_ee_true = entry.Key("T_base_ee_true").Rigid(false);
    for (const auto& [camera, points] :
         entry.Key("points_px").Members("an object {camera name: {\"ids\", \"px\"}}")) {
      if (!truth.T_cam.count(camera))
        throw points.Error("unknown camera '" + camera + "'; expected one of " + keys.cam);
      points.ExpectObject("an object {\"ids\": [...], \"px\": [[u, v], ...]}");
      points.RejectUnknownKeys({"ids", "px"});
      Observation view;
      view.pose_id = pose.id;
      view.camera = camera;
      ReadIdsAndPixels(points.Key("ids"), points.Key("px"), nullptr, &view);
      pose.points_px[camera] = std::move(view);
    }
    truth.poses.push_back(std::move(pose));
  }
  return truth;
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

OrderedJson PixelsJson(const std::vector<Eigen::Vector2d>& points) {
  OrderedJson px = OrderedJson::array();
  for (const auto& p : points) px.push_back({p.x(), p.y()});
  return px;
}

}  // namespace

Dataset LoadDataset(const std::string& path, const LoadOptions& options,
                    std::vector<std::string>* warnings) {
  const nlohmann::json doc = ReadJsonFile(path);
  return DatasetFromJson(doc, path, options, warnings);
}

Dataset DatasetFromJson(const nlohmann::json& doc, const std::string& path, const LoadOptions& options,
                        std::vector<std::string>* warnings) {
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
    for (const auto& w : dataset.target->Warnings()) warnings->push_back(path + ": " + w);
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

GroundTruth LoadGroundTruth(const std::string& path) {
  const nlohmann::json doc = ReadJsonFile(path);
  const JsonReader root(&doc, path);
  root.ExpectObject(std::string("a ") + kGroundTruthFormat + " object");
  const JsonReader format_json = root.Key("format");
  const std::string format =
      format_json.NonEmptyString(std::string("\"") + kGroundTruthFormat + "\"");
  if (format == kGroundTruthFormat) return ReadGroundTruth(root, std::nullopt);
  if (format == kDatasetFormat || format == kObservationsFormat) {
    if (!root.Has("ground_truth"))
      throw InputError(path, "/ground_truth",
                       std::string("missing key; expected a ") + kGroundTruthFormat +
                           " file or a dataset with a ground_truth object");
    return ReadGroundTruth(root.Key("ground_truth"), ReadSetup(root.Key("setup")));
  }
  throw format_json.Error("unsupported format '" + format + "'; expected \"" + kGroundTruthFormat +
                          "\" (or a dataset with a ground_truth object)");
}

void SaveGroundTruth(const GroundTruth& truth, const std::string& path) {
  const TruthKeys keys = KeysOf(truth.setup);
  OrderedJson j = OrderedJson::object();
  j["format"] = kGroundTruthFormat;
  j["setup"] = SetupName(truth.setup);
  OrderedJson cams = OrderedJson::object();
  for (const auto& [name, T] : truth.T_cam) cams[name] = JsonFromTransform(T);
  j[keys.cam] = cams;
  if (truth.has_T_target) j[keys.target] = JsonFromTransform(truth.T_target);
  if (!truth.poses.empty()) {
    OrderedJson poses = OrderedJson::array();
    for (const auto& pose : truth.poses) {
      OrderedJson p = OrderedJson::object();
      p["id"] = pose.id;
      p["T_base_ee_true"] = JsonFromTransform(pose.T_base_ee_true);
      OrderedJson points = OrderedJson::object();
      for (const auto& [camera, view] : pose.points_px) {
        OrderedJson v = OrderedJson::object();
        v["ids"] = view.ids;
        v["px"] = PixelsJson(view.points_px);
        points[camera] = v;
      }
      p["points_px"] = points;
      poses.push_back(p);
    }
    j["poses"] = poses;
  }
  WriteFileAtomically(path, DumpJson(j));
}

}  // namespace handeye
