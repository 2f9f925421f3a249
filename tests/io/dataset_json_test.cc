// SPDX-License-Identifier: GPL-2.0-or-later
// Dataset and observation files (SPEC §4, §5): round trips (the bad inputs
// are in dataset_json_bad_input_test.cc).
#include "handeye/io/dataset_json.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "handeye/core/error.h"
#include "dataset_json_fixtures.h"
#include "handeye/core/transform.h"
#include "handeye/detectors/registry.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using namespace handeye::test;

TEST_CASE("A valid dataset loads, with image paths resolved against its folder", "[io][dataset]") {
  const std::string dir = test::TempDir("dataset_valid");
  std::vector<Warning> warnings;
  const Dataset d = LoadDataset(WriteJson(dir + "/data.json", ValidDatasetJson()), {}, &warnings);
  CHECK(warnings.empty());  // 4 + 3 is odd: not ambiguous
  CHECK(d.setup == Setup::kEyeToHand);
  REQUIRE(d.target);
  CHECK(d.target->Type() == "checkerboard");
  CHECK(d.target->Points().size() == 12);
  REQUIRE(d.cameras.size() == 2);
  CHECK(d.cameras[0].num_distortion == 0);
  CHECK(d.cameras[1].num_distortion == 5);
  CHECK(d.cameras[1].Distortion() == std::vector<double>{0.1, -0.2, 0.001, 0.002, 0.05});
  CHECK(d.cameras[1].fy() == 501);
  REQUIRE(d.poses.size() == 3);
  CHECK(d.poses[1].T_base_ee.translation() == Eigen::Vector3d(0.4, 0.1, 0.9));
  CHECK(d.poses[0].images.at("cam1") == dir + "/cam1/0001.png");
  CHECK(d.poses[1].images.at("cam0") == dir + "/cam0/0002.png");
  CHECK(d.poses[2].images.at("cam1") == "/data/elsewhere/0003.png");
  CHECK(d.observations.empty());
}

TEST_CASE("An ambiguous checkerboard is loaded with a warning", "[io][dataset]") {
  json j = ValidDatasetJson();
  j["target"]["inner_corners"] = {4, 4};
  std::vector<Warning> warnings;
  const std::string file = WriteJson(test::TempDir("dataset_warn") + "/data.json", j);
  LoadDataset(file, {}, &warnings);
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0].text, Contains(file));
  CHECK_THAT(warnings[0].text, Contains("ambiguous"));
  CHECK(warnings[0].kind == WarningKind::kTargetAmbiguous);
}

Dataset MakeDataset(const std::string& image_dir) {
  Dataset d;
  d.setup = Setup::kEyeInHand;
  TargetSpec spec;
  spec.type = "checkerboard";
  spec.values["inner_corners"] = std::vector<double>{5, 4};
  spec.values["square_size_m"] = 0.0301;
  d.target = MakeTarget(spec);
  std::string why;
  d.cameras.push_back(*Camera::Make("left", 1280, 1024, 1100.123456789, 1101.987654321, 639.4999999,
                                    511.25, {}, &why));
  d.cameras.push_back(*Camera::Make("right", 1280, 1024, 900.5, 900.25, 640.0, 512.0,
                                    {-0.31, 0.12, 1e-4, -2e-4, -0.02, 0.001, 0.002, 0.003}, &why));
  for (int i = 0; i < 4; ++i) {
    RobotPose pose;
    pose.id = "p" + std::to_string(i);
    pose.T_base_ee = MakeTransformFromRotationVector(
        Eigen::Vector3d(0.1 + 0.37 * i, -0.2 * i, 1.0 / (i + 3.0)),
        Eigen::Vector3d(0.4 + 0.01 * i, 1.0 / 3.0, 0.9 - std::sqrt(2.0) * 0.01 * i));
    pose.images["left"] = image_dir + "/left/" + pose.id + ".png";
    if (i != 2) pose.images["right"] = image_dir + "/right/" + pose.id + ".png";
    d.poses.push_back(pose);
  }
  return d;
}

void CheckSameModel(const Dataset& a, const Dataset& b) {
  CHECK(a.setup == b.setup);
  CHECK(a.target->Type() == b.target->Type());
  REQUIRE(a.target->Points().size() == b.target->Points().size());
  for (std::size_t k = 0; k < a.target->Points().size(); ++k)
    CHECK(a.target->Points()[k].p_target == b.target->Points()[k].p_target);
  REQUIRE(a.cameras.size() == b.cameras.size());
  for (std::size_t c = 0; c < a.cameras.size(); ++c) {
    CHECK(a.cameras[c].name == b.cameras[c].name);
    CHECK(a.cameras[c].width == b.cameras[c].width);
    CHECK(a.cameras[c].height == b.cameras[c].height);
    CHECK(a.cameras[c].params == b.cameras[c].params);  // exact
    CHECK(a.cameras[c].num_distortion == b.cameras[c].num_distortion);
  }
  REQUIRE(a.poses.size() == b.poses.size());
  for (std::size_t p = 0; p < a.poses.size(); ++p) {
    CHECK(a.poses[p].id == b.poses[p].id);
    CHECK(a.poses[p].T_base_ee.matrix() == b.poses[p].T_base_ee.matrix());  // exact
  }
}

TEST_CASE("Dataset round trip: exact numbers, image paths relative in the file", "[io][dataset]") {
  const std::string dir = test::TempDir("dataset_roundtrip");
  const Dataset original = MakeDataset(dir + "/images");
  SaveDataset(original, dir + "/dataset.json");
  const std::string text = test::ReadText(dir + "/dataset.json");
  CHECK_THAT(text, Contains("\"left\": \"images/left/p0.png\""));
  CHECK_THAT(text, !Contains(dir));

  const Dataset loaded = LoadDataset(dir + "/dataset.json");
  CheckSameModel(original, loaded);
  for (std::size_t p = 0; p < original.poses.size(); ++p)
    CHECK(loaded.poses[p].images == original.poses[p].images);

  // Saved again, from a folder deeper down: paths become ../images/...
  std::filesystem::create_directories(dir + "/sub");
  SaveDataset(loaded, dir + "/sub/dataset.json");
  CHECK_THAT(test::ReadText(dir + "/sub/dataset.json"), Contains("\"../images/left/p0.png\""));
  const Dataset again = LoadDataset(dir + "/sub/dataset.json");
  CheckSameModel(original, again);
  for (std::size_t p = 0; p < original.poses.size(); ++p)
    CHECK(again.poses[p].images == original.poses[p].images);
  // Byte-identical once the paths are relative to the same folder.
  SaveDataset(again, dir + "/again.json");
  CHECK(test::ReadText(dir + "/again.json") == text);
}

TEST_CASE("SaveDataset never writes a file that LoadDataset would reject", "[io][dataset]") {
  const std::string dir = test::TempDir("dataset_save_invalid");
  Dataset d = MakeDataset(dir);
  d.poses[1].images["middle"] = dir + "/middle.png";
  CHECK_THROWS_AS(SaveDataset(d, dir + "/dataset.json"), std::invalid_argument);
  CHECK_FALSE(std::filesystem::exists(dir + "/dataset.json"));
}

TEST_CASE("Observations round trip, exactly and in order", "[io][dataset]") {
  const std::string dir = test::TempDir("observations_roundtrip");
  Dataset original = MakeDataset(dir);
  for (const auto& pose : original.poses)
    for (const auto& camera : original.cameras) {
      Observation view;
      view.pose_id = pose.id;
      view.camera = camera.name;
      for (int id : {19, 0, 7}) {
        view.ids.push_back(id);
        view.points_px.emplace_back(100.0 / 3.0 + id, 1e-9 * id - 0.5);
      }
      original.observations.push_back(view);
    }
  SaveObservations(original, dir + "/obs.json");
  CHECK_THAT(test::ReadText(dir + "/obs.json"), !Contains("images"));
  const Dataset loaded = LoadDataset(dir + "/obs.json");
  CheckSameModel(original, loaded);
  for (const auto& pose : loaded.poses) CHECK(pose.images.empty());
  REQUIRE(loaded.observations.size() == original.observations.size());
  for (std::size_t k = 0; k < loaded.observations.size(); ++k) {
    const Observation& a = original.observations[k];
    const Observation& b = loaded.observations[k];
    CHECK(a.pose_id == b.pose_id);
    CHECK(a.camera == b.camera);
    CHECK(a.ids == b.ids);
    CHECK(a.points_px == b.points_px);  // exact
  }
  SaveObservations(loaded, dir + "/obs2.json");
  CHECK(test::ReadText(dir + "/obs2.json") == test::ReadText(dir + "/obs.json"));
}


}  // namespace
}  // namespace handeye
