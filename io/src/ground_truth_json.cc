// SPDX-License-Identifier: GPL-2.0-or-later
// handeye-ground-truth/1 files and a dataset's `ground_truth` object (SPEC §4),
// and the pieces the dataset reader shares with them.
#include <map>
#include <optional>
#include <string>

#include "dataset_json_internal.h"
#include "handeye/core/error.h"
#include "handeye/core/setup_frames.h"
#include "handeye/io/atomic_file.h"
#include "handeye/io/dataset_json.h"

namespace handeye {
namespace internal {

Setup ReadSetup(const JsonReader& r) {
  const std::string name = r.NonEmptyString("a setup, \"eye_to_hand\" or \"eye_in_hand\"");
  const auto setup = ParseSetup(name);
  if (!setup)
    throw r.Error("unknown setup '" + name + "'; expected \"eye_to_hand\" or \"eye_in_hand\"");
  return *setup;
}

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

nlohmann::ordered_json PixelsJson(const std::vector<Eigen::Vector2d>& points) {
  nlohmann::ordered_json px = nlohmann::ordered_json::array();
  for (const auto& p : points) px.push_back({p.x(), p.y()});
  return px;
}

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
  const SetupFrames keys = FramesOf(truth.setup);
  const SetupFrames other = FramesOf(truth.setup == Setup::kEyeToHand ? Setup::kEyeInHand : Setup::kEyeToHand);
  for (const std::string& key : {other.camera_key, other.target_key})
    if (r.Has(key))
      throw r.Key(key).Error(key + " belongs to " + SetupName(other.setup) + " ground truth; for " +
                             SetupName(truth.setup) + " expected " + keys.camera_key + " and " + keys.target_key);
  r.RejectUnknownKeys({"format", "setup", keys.camera_key, keys.target_key, "poses"});

  const JsonReader cams = r.Key(keys.camera_key);
  for (const auto& [name, T] : cams.Members("an object {camera name: 4x4 transform}"))
    truth.T_cam[name] = T.Rigid(false);
  if (truth.T_cam.empty()) throw cams.Error("expected at least one camera");
  truth.has_T_target = r.Has(keys.target_key);
  if (truth.has_T_target) truth.T_target = r.Key(keys.target_key).Rigid(false);

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
        throw points.Error("unknown camera '" + camera + "'; expected one of " + keys.camera_key);
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

}  // namespace internal

using OrderedJson = nlohmann::ordered_json;
using internal::kDatasetFormat;
using internal::kGroundTruthFormat;
using internal::kObservationsFormat;

GroundTruth LoadGroundTruth(const std::string& path) {
  const nlohmann::json doc = ReadJsonFile(path);
  const JsonReader root(&doc, path);
  root.ExpectObject(std::string("a ") + kGroundTruthFormat + " object");
  const JsonReader format_json = root.Key("format");
  const std::string format =
      format_json.NonEmptyString(std::string("\"") + kGroundTruthFormat + "\"");
  if (format == kGroundTruthFormat) return internal::ReadGroundTruth(root, std::nullopt);
  if (format == kDatasetFormat || format == kObservationsFormat) {
    if (!root.Has("ground_truth"))
      throw InputError(path, "/ground_truth",
                       std::string("missing key; expected a ") + kGroundTruthFormat +
                           " file or a dataset with a ground_truth object");
    return internal::ReadGroundTruth(root.Key("ground_truth"), internal::ReadSetup(root.Key("setup")));
  }
  throw format_json.Error("unsupported format '" + format + "'; expected \"" + kGroundTruthFormat +
                          "\" (or a dataset with a ground_truth object)");
}

void SaveGroundTruth(const GroundTruth& truth, const std::string& path) {
  const SetupFrames keys = FramesOf(truth.setup);
  OrderedJson j = OrderedJson::object();
  j["format"] = kGroundTruthFormat;
  j["setup"] = SetupName(truth.setup);
  OrderedJson cams = OrderedJson::object();
  for (const auto& [name, T] : truth.T_cam) cams[name] = JsonFromTransform(T);
  j[keys.camera_key] = cams;
  if (truth.has_T_target) j[keys.target_key] = JsonFromTransform(truth.T_target);
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
        v["px"] = internal::PixelsJson(view.points_px);
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
