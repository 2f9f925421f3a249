// SPDX-License-Identifier: GPL-2.0-or-later
// Ground-truth files (`handeye-ground-truth/1`, or a dataset's ground_truth
// object): round trips and bad input.
#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "handeye/io/dataset_json.h"
#include "support/input_error.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;
using nlohmann::json;

Eigen::Isometry3d SomeTransform(double k) {
  return MakeTransformFromRotationVector(Eigen::Vector3d(0.3 * k, -1.1 + k, 0.7 / (1 + k)),
                                         Eigen::Vector3d(k / 3.0, -2.0 * k, 1.0 / 7.0));
}

GroundTruth MakeTruth(Setup setup) {
  GroundTruth truth;
  truth.setup = setup;
  truth.T_cam["cam0"] = SomeTransform(1);
  truth.T_cam["cam1"] = SomeTransform(2);
  truth.T_target = SomeTransform(3);
  for (int i = 0; i < 3; ++i) {
    GroundTruth::PoseTruth pose;
    pose.id = "000" + std::to_string(i);
    pose.T_base_ee_true = SomeTransform(4 + i);
    Observation view;
    view.pose_id = pose.id;
    view.camera = "cam1";
    view.ids = {3, 1, 2};
    view.points_px = {{1.0 / 3.0, 2.5}, {100.125, -0.1}, {1e-7, 1919.9999999}};
    pose.points_px["cam1"] = view;
    truth.poses.push_back(pose);
  }
  return truth;
}

void CheckSameTruth(const GroundTruth& a, const GroundTruth& b) {
  CHECK(a.setup == b.setup);
  REQUIRE(a.T_cam.size() == b.T_cam.size());
  for (const auto& [name, T] : a.T_cam) CHECK(b.T_cam.at(name).matrix() == T.matrix());
  CHECK(a.has_T_target == b.has_T_target);
  if (a.has_T_target) CHECK(a.T_target.matrix() == b.T_target.matrix());
  REQUIRE(a.poses.size() == b.poses.size());
  for (std::size_t i = 0; i < a.poses.size(); ++i) {
    CHECK(a.poses[i].id == b.poses[i].id);
    CHECK(a.poses[i].T_base_ee_true.matrix() == b.poses[i].T_base_ee_true.matrix());
    REQUIRE(a.poses[i].points_px.size() == b.poses[i].points_px.size());
    for (const auto& [camera, view] : a.poses[i].points_px) {
      const Observation& other = b.poses[i].points_px.at(camera);
      CHECK(other.pose_id == view.pose_id);
      CHECK(other.camera == camera);
      CHECK(other.ids == view.ids);
      CHECK(other.points_px == view.points_px);
    }
  }
}

TEST_CASE("Ground truth round trip, both setups", "[io][truth]") {
  const std::string dir = test::TempDir("truth_roundtrip");
  for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    const GroundTruth truth = MakeTruth(setup);
    SaveGroundTruth(truth, dir + "/gt.json");
    const std::string text = test::ReadText(dir + "/gt.json");
    if (setup == Setup::kEyeToHand) {
      CHECK_THAT(text, Contains("\"T_base_cam\""));
      CHECK_THAT(text, Contains("\"T_ee_target\""));
    } else {
      CHECK_THAT(text, Contains("\"T_ee_cam\""));
      CHECK_THAT(text, Contains("\"T_base_target\""));
    }
    CheckSameTruth(truth, LoadGroundTruth(dir + "/gt.json"));
  }
}

TEST_CASE("Ground truth without the target pose leaves it out", "[io][truth]") {
  const std::string dir = test::TempDir("truth_no_target");
  GroundTruth truth = MakeTruth(Setup::kEyeToHand);
  truth.has_T_target = false;
  truth.poses.clear();
  SaveGroundTruth(truth, dir + "/gt.json");
  const std::string text = test::ReadText(dir + "/gt.json");
  CHECK_THAT(text, !Contains("T_ee_target"));
  CHECK_THAT(text, !Contains("poses"));
  const GroundTruth loaded = LoadGroundTruth(dir + "/gt.json");
  CHECK_FALSE(loaded.has_T_target);
  CheckSameTruth(truth, loaded);
}

TEST_CASE("Ground truth can live in a dataset's ground_truth object", "[io][truth]") {
  const std::string dir = test::TempDir("truth_in_dataset");
  const GroundTruth truth = MakeTruth(Setup::kEyeInHand);
  SaveGroundTruth(truth, dir + "/gt.json");
  json nested = json::parse(test::ReadText(dir + "/gt.json"));
  nested.erase("format");
  nested.erase("setup");  // inherited from the dataset
  json dataset = json::parse(R"({
    "format": "handeye-dataset/1", "setup": "eye_in_hand",
    "target": {"type": "checkerboard", "inner_corners": [4, 3], "square_size_m": 0.05},
    "cameras": [{"name": "cam0", "image_size": [64, 48],
                 "intrinsics": {"fx": 50, "fy": 50, "cx": 32, "cy": 24},
                 "distortion": {"model": "none"}}],
    "poses": [{"id": "1", "T_base_ee": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "images": {}}]
  })");
  dataset["ground_truth"] = nested;
  test::WriteText(dir + "/dataset.json", dataset.dump(1));
  CheckSameTruth(truth, LoadGroundTruth(dir + "/dataset.json"));
  CHECK_NOTHROW(LoadDataset(dir + "/dataset.json"));

  dataset["ground_truth"]["setup"] = "eye_to_hand";
  test::WriteText(dir + "/dataset.json", dataset.dump(1));
  try {
    LoadGroundTruth(dir + "/dataset.json");
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.json_path() == "/ground_truth/setup");
    CHECK_THAT(e.what(), Contains("expected the dataset's setup \"eye_in_hand\""));
  }

  dataset.erase("ground_truth");
  test::WriteText(dir + "/dataset.json", dataset.dump(1));
  try {
    LoadGroundTruth(dir + "/dataset.json");
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.file() == dir + "/dataset.json");
    CHECK(e.json_path() == "/ground_truth");
    CHECK_THAT(e.what(), Contains("missing key; expected a handeye-ground-truth/1 file"));
  }
}

json ValidTruthJson() {
  return json::parse(R"({
    "format": "handeye-ground-truth/1", "setup": "eye_to_hand",
    "T_base_cam": {"cam0": [[1,0,0,1],[0,1,0,2],[0,0,1,3],[0,0,0,1]],
                   "cam1": [[0,-1,0,1],[1,0,0,2],[0,0,1,3],[0,0,0,1]]},
    "T_ee_target": [[1,0,0,0],[0,1,0,0],[0,0,1,0.1],[0,0,0,1]],
    "poses": [
      {"id": "a", "T_base_ee_true": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]],
       "points_px": {"cam0": {"ids": [0, 1], "px": [[1, 2], [3, 4]]}}},
      {"id": "b", "T_base_ee_true": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]],
       "points_px": {}}
    ]
  })");
}

void RequireTruthError(const json& j, const std::string& json_path, const std::string& expected) {
  const std::string file = test::TempDir("truth_bad") + "/gt.json";
  test::WriteText(file, j.dump(2));
  test::RequireInputErrorAt(file, json_path, expected, [&] { LoadGroundTruth(file); });
}

TEST_CASE("Ground truth: bad input is named precisely", "[io][truth][bad]") {
  {
    const std::string dir = test::TempDir("truth_valid");
    test::WriteText(dir + "/gt.json", ValidTruthJson().dump());
    const GroundTruth truth = LoadGroundTruth(dir + "/gt.json");
    CHECK(truth.T_cam.size() == 2);
    CHECK(truth.has_T_target);
    CHECK(truth.poses.size() == 2);
  }
  const std::string missing = test::TempDir("truth_missing") + "/gt.json";
  CHECK_THROWS_WITH(LoadGroundTruth(missing), Contains(missing + ": file does not exist"));

  json j = ValidTruthJson();
  j["format"] = "handeye-result/1";
  RequireTruthError(j, "/format", "unsupported format 'handeye-result/1'");

  j = ValidTruthJson();
  j["setup"] = "eye-to-hand";
  RequireTruthError(j, "/setup", "unknown setup 'eye-to-hand'");

  j = ValidTruthJson();
  j["T_ee_cam"] = j["T_base_cam"];
  RequireTruthError(j, "/T_ee_cam", "T_ee_cam belongs to eye_in_hand ground truth");

  j = ValidTruthJson();
  j["T_base_cams"] = j["T_base_cam"];
  RequireTruthError(j, "/T_base_cams", "unknown key 'T_base_cams' (did you mean 'T_base_cam'?)");

  j = ValidTruthJson();
  j.erase("T_base_cam");
  RequireTruthError(j, "/T_base_cam",
                    "missing key; expected an object {camera name: 4x4 transform}");

  j = ValidTruthJson();
  j["T_base_cam"] = json::object();
  RequireTruthError(j, "/T_base_cam", "expected at least one camera");

  j = ValidTruthJson();
  j["T_base_cam"]["cam1"][0][0] = 0.5;
  RequireTruthError(j, "/T_base_cam/cam1", "expected a rigid 4x4 transform");

  j = ValidTruthJson();
  j["T_ee_target"][1][3] = "0.1";
  RequireTruthError(j, "/T_ee_target/1/3", "got the string \"0.1\"");

  j = ValidTruthJson();
  j["poses"][1]["id"] = "a";
  RequireTruthError(j, "/poses/1/id", "duplicate pose id 'a' (also at /poses/0)");

  j = ValidTruthJson();
  j["poses"][0]["T_base_ee_true"][3][3] = 0;
  RequireTruthError(j, "/poses/0/T_base_ee_true", "last row is [0, 0, 0, 1]");

  j = ValidTruthJson();
  j["poses"][1]["points_px"]["cam9"] = j["poses"][0]["points_px"]["cam0"];
  RequireTruthError(j, "/poses/1/points_px/cam9", "unknown camera 'cam9'");

  j = ValidTruthJson();
  j["poses"][0]["points_px"]["cam0"]["px"].erase(0);
  RequireTruthError(j, "/poses/0/points_px/cam0/px", "expected 2 pixels [u, v], one per id, got 1");

  j = ValidTruthJson();
  j["poses"][0]["points_px"]["cam0"]["ids"] = {4, 4};
  RequireTruthError(j, "/poses/0/points_px/cam0/ids/1", "duplicate id 4");

  j = ValidTruthJson();
  j["poses"][0]["pixels"] = json::object();
  RequireTruthError(j, "/poses/0/pixels", "unknown key 'pixels'");
}

}  // namespace
}  // namespace handeye
