// SPDX-License-Identifier: GPL-2.0-or-later
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "handeye/core/checkerboard.h"
#include "handeye/io/dataset_json.h"
#include "support/test_support.h"

using namespace handeye;
namespace fs = std::filesystem;

namespace {

// Small images keep the test to about a second; the geometry is the preset's.
const char* kTinyScene = "--cell small --cameras 2 --poses 3 --image-size 640x360 --seed 3";

}  // namespace

TEST_CASE("simulate writes a dataset, its ground truth and one image per view", "[simulate]") {
  const std::string dir = test::TempDir("simulate_tiny");
  std::string output;
  REQUIRE(test::RunHandeye("simulate " + dir + " " + kTinyScene, &output) == 0);
  INFO(output);
  CHECK_THAT(output, Catch::Contains("2 cameras, 3 poses"));

  const Dataset dataset = LoadDataset(dir + "/dataset.json");
  CHECK(dataset.setup == Setup::kEyeToHand);
  REQUIRE(dataset.cameras.size() == 2);
  REQUIRE(dataset.poses.size() == 3);
  CHECK(dataset.cameras[0].width == 640);
  CHECK(dataset.cameras[0].height == 360);
  const auto* board = dynamic_cast<const CheckerboardTarget*>(dataset.target.get());
  REQUIRE(board);
  CHECK(board->cols() == 7);
  CHECK(board->rows() == 4);
  CHECK(board->square_size_m() == 0.04);

  const GroundTruth truth = LoadGroundTruth(dir + "/ground_truth.json");
  CHECK(truth.setup == Setup::kEyeToHand);
  CHECK(truth.T_cam.size() == 2);
  REQUIRE(truth.poses.size() == 3);
  int views = 0;
  for (size_t j = 0; j < truth.poses.size(); ++j) {
    const RobotPose& pose = dataset.poses[j];
    CHECK(truth.poses[j].id == pose.id);
    // No pose noise requested: reported poses are the true ones.
    CHECK((truth.poses[j].T_base_ee_true.matrix() - pose.T_base_ee.matrix()).norm() < 1e-12);
    // An image for every camera, as a real capture: those that see the whole
    // board and those that do not.
    CHECK(pose.images.size() == dataset.cameras.size());
    for (const auto& [camera, obs] : truth.poses[j].points_px) {
      REQUIRE(pose.images.count(camera));
      CHECK(fs::path(pose.images.at(camera)).filename() == pose.id + ".png");
      CHECK(fs::is_regular_file(pose.images.at(camera)));
      CHECK(obs.ids.size() == board->Points().size());
      ++views;
    }
  }
  CHECK(views >= 3);
}

TEST_CASE("simulate --visible-only, --swap-poses and --see-through", "[simulate]") {
  const std::string dir = test::TempDir("simulate_faults");
  std::string output;
  REQUIRE(test::RunHandeye("simulate " + dir + " " + kTinyScene +
                               " --visible-only --swap-poses 1 --see-through",
                           &output) == 0);
  INFO(output);
  const Dataset dataset = LoadDataset(dir + "/dataset.json");
  const GroundTruth truth = LoadGroundTruth(dir + "/ground_truth.json");
  int swapped = 0;
  for (size_t j = 0; j < truth.poses.size(); ++j) {
    // --visible-only: an image exactly for each camera that sees the whole board.
    CHECK(dataset.poses[j].images.size() == truth.poses[j].points_px.size());
    if ((truth.poses[j].T_base_ee_true.matrix() - dataset.poses[j].T_base_ee.matrix()).norm() > 1e-9) {
      // The record is another pose's.
      bool another = false;
      for (const auto& other : truth.poses)
        another = another || (other.T_base_ee_true.matrix() - dataset.poses[j].T_base_ee.matrix()).norm() < 1e-12;
      CHECK(another);
      ++swapped;
    }
  }
  CHECK(swapped == 2);
  CHECK_THAT(output, Catch::Contains("exchanged (--swap-poses)"));
  std::string bad;
  CHECK(test::RunHandeye("simulate " + dir + "/bad " + kTinyScene + " --swap-poses 2", &bad) == 2);
  CHECK_THAT(bad, Catch::Contains("swapped pose pairs"));
}

TEST_CASE("simulate output does not depend on the number of threads", "[simulate]") {
  const std::string one = test::TempDir("simulate_threads_1");
  const std::string two = test::TempDir("simulate_threads_2");
  std::string output;
  REQUIRE(test::RunHandeye("simulate " + one + " " + kTinyScene + " --threads 1", &output) == 0);
  REQUIRE(test::RunHandeye("simulate " + two + " " + kTinyScene + " --threads 2", &output) == 0);
  CHECK(test::ReadText(one + "/dataset.json") == test::ReadText(two + "/dataset.json"));
  CHECK(test::ReadText(one + "/ground_truth.json") == test::ReadText(two + "/ground_truth.json"));
  int images = 0;
  for (const auto& entry : fs::recursive_directory_iterator(one + "/images")) {
    if (!entry.is_regular_file()) continue;
    const fs::path relative = fs::relative(entry.path(), one);
    INFO(relative);
    REQUIRE(fs::is_regular_file(fs::path(two) / relative));
    CHECK(test::ReadText(entry.path().string()) == test::ReadText((fs::path(two) / relative).string()));
    ++images;
  }
  CHECK(images >= 3);
}

TEST_CASE("simulate --preset metric-medium uses METRIC's cameras and 4x3 board", "[simulate]") {
  const std::string dir = test::TempDir("simulate_metric");
  std::string output;
  REQUIRE(test::RunHandeye("simulate " + dir + " --preset metric-medium --poses 2 --image-size 480x270",
                           &output) == 0);
  INFO(output);
  const Dataset dataset = LoadDataset(dir + "/dataset.json");
  REQUIRE(dataset.cameras.size() == 4);
  // 1371.02 px at 1920 wide, scaled to 480.
  CHECK(dataset.cameras[0].fx() == Approx(1371.02 / 4));
  CHECK_FALSE(dataset.cameras[0].HasDistortion());
  const auto* board = dynamic_cast<const CheckerboardTarget*>(dataset.target.get());
  REQUIRE(board);
  CHECK(board->cols() == 4);
  CHECK(board->rows() == 3);
  CHECK(board->square_size_m() == 0.05);
}

TEST_CASE("simulate rejects bad options with exit code 2 and says which", "[simulate]") {
  const std::string dir = test::TempDir("simulate_bad");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--cameras 0", "cameras"},
      {"--poses 0", "poses"},
      {"--cell huge", "huge"},
      {"--cell metric-medium", "--preset"},
      {"--preset tiny", "--preset"},
      {"--cell small --preset metric-medium", "not both"},
      {"--setup sideways", "--setup"},
      {"--board 7by4", "--board"},
      {"--square -1", "--square"},
      {"--target nosuch", "unknown target type"},
      {"--image-size 10x10", "image size"},
      {"--pose-noise-mm -1", "translation noise"},
      {"--blur -1", "blur"},
      {"--poor-camera cam1:3", "--poor-camera"},
      {"--poor-camera cam9:3:8", "cam0 … cam3"},
      {"--poor-camera cam1:-3:8", "0 or more"},
      {"--threads -1", "--threads"},
  };
  for (const auto& [args, message] : cases) {
    std::string output;
    INFO(args);
    CHECK(test::RunHandeye("simulate " + dir + " " + args, &output) == 2);
    CHECK_THAT(output, Catch::Contains(message));
    CHECK_FALSE(fs::exists(dir + "/dataset.json"));
  }
}
