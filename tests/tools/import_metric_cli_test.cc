// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye import-metric`: exit codes, messages and what it writes (SPEC §7, §8).
#include <catch2/catch.hpp>
#include <filesystem>

#include "handeye/io/dataset_json.h"
#include "io/io_fixtures.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;
namespace fs = std::filesystem;

TEST_CASE("handeye import-metric writes a dataset and its ground truth", "[tools][metric]") {
  const std::string dir = test::TempDir("cli_import_metric");
  test::WriteMetricFolder(dir + "/in", 1, true);
  fs::create_directories(dir + "/out");
  std::string out;
  REQUIRE(test::RunHandeye("import-metric '" + dir + "/in' -o '" + dir + "/out/dataset.json'",
                           &out) == 0);
  CHECK_THAT(out, Contains("2 cameras, 4 poses, 6 images, setup eye_to_hand"));

  // Image paths in the file are relative to it, and resolve to the images.
  const std::string text = test::ReadText(dir + "/out/dataset.json");
  CHECK_THAT(text, Contains("\"camera1\": \"../in/camera1/image/0001.png\""));
  const Dataset d = LoadDataset(dir + "/out/dataset.json");
  CHECK(d.cameras.size() == 2);
  CHECK(d.poses.size() == 4);
  for (const auto& pose : d.poses)
    for (const auto& [camera, image] : pose.images) CHECK(fs::is_regular_file(image));

  const GroundTruth truth = LoadGroundTruth(dir + "/out/ground_truth.json");
  CHECK(truth.setup == Setup::kEyeToHand);
  CHECK_FALSE(truth.has_T_target);
  REQUIRE(truth.T_cam.count("camera2"));
  CHECK(
      (truth.T_cam.at("camera2").matrix() - test::MetricCamera(2).matrix()).cwiseAbs().maxCoeff() <
      1e-15);
}

TEST_CASE("handeye import-metric without GT writes no ground truth", "[tools][metric]") {
  const std::string dir = test::TempDir("cli_import_metric_nogt");
  test::WriteMetricFolder(dir + "/in", 0, false);
  std::string out;
  REQUIRE(test::RunHandeye("import-metric '" + dir + "/in' -o '" + dir + "/dataset.json'", &out) ==
          0);
  CHECK_THAT(out, Contains("setup eye_in_hand"));
  CHECK(fs::is_regular_file(dir + "/dataset.json"));
  CHECK_FALSE(fs::exists(dir + "/ground_truth.json"));
}

TEST_CASE("handeye import-metric: bad input exits with 2 and names the file",
          "[tools][metric][bad]") {
  const std::string dir = test::TempDir("cli_import_metric_bad");
  std::string out;
  CHECK(test::RunHandeye("import-metric '" + dir + "/nope' -o '" + dir + "/d.json'", &out) == 2);
  CHECK_THAT(out, Contains("error: " + dir + "/nope: folder does not exist"));

  test::WriteMetricFolder(dir + "/in", 1, true);
  fs::remove(dir + "/in/camera1/pose/0002.csv");
  CHECK(test::RunHandeye("import-metric '" + dir + "/in' -o '" + dir + "/d.json'", &out) == 2);
  CHECK_THAT(out,
             Contains("error: " + dir + "/in/camera1/pose/0002.csv: pose file does not exist"));
  CHECK_FALSE(fs::exists(dir + "/d.json"));

  test::WriteText(dir + "/in/camera1/pose/0002.csv", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 x\n");
  CHECK(test::RunHandeye("import-metric '" + dir + "/in' -o '" + dir + "/d.json'", &out) == 2);
  CHECK_THAT(out, Contains("line 4, value 4: expected a finite number, got 'x'"));

  CHECK(test::RunHandeye("import-metric '" + dir + "/in'", &out) == 2);
  CHECK_THAT(out, Contains("--output is required"));
}

}  // namespace
}  // namespace handeye
