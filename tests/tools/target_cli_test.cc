// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye target` (printable sheets) and `handeye simulate` with ChArUco and
// AprilGrid targets, through to calibration.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "handeye/core/aprilgrid.h"
#include "handeye/core/charuco.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/json_util.h"
#include "support/test_support.h"

using namespace handeye;
namespace fs = std::filesystem;

namespace {

std::shared_ptr<const Target> TargetFromFile(const std::string& path) {
  const nlohmann::json json = ReadJsonFile(path);
  return MakeTarget(TargetSpecFromJson(JsonReader(&json, path)));
}

/// Pixels per metre of a PNG's pHYs chunk, 0 when it has none.
std::uint32_t PixelsPerMetre(const std::string& png) {
  const auto at = png.find("pHYs");
  if (at == std::string::npos || at + 13 > png.size()) return 0;
  std::uint32_t value = 0;
  for (int i = 0; i < 4; ++i) value = (value << 8) | static_cast<std::uint8_t>(png[at + 4 + i]);
  return png[at + 12] == 1 ? value : 0;
}

}  // namespace

TEST_CASE("target draws the default ChArUco sheet at the given dpi with its target object",
          "[cli][target]") {
  const std::string dir = test::TempDir("target_charuco");
  std::string out;
  REQUIRE(test::RunHandeye("target charuco -o " + dir + "/board.png --dpi 100", &out) == 0);
  INFO(out);
  const auto target = TargetFromFile(dir + "/board.json");
  const auto* board = dynamic_cast<const CharucoTarget*>(target.get());
  REQUIRE(board);
  CHECK(board->squares_x() == 7);
  CHECK(board->squares_y() == 5);
  CHECK(board->dictionary().name == "DICT_5X5_100");
  const std::string png = test::ReadText(dir + "/board.png");
  CHECK(PixelsPerMetre(png) == 3937);  // 100 dpi
  const cv::Mat image = cv::imread(dir + "/board.png", cv::IMREAD_GRAYSCALE);
  REQUIRE(!image.empty());
  const Eigen::AlignedBox2d extent = board->Extent();
  const double pitch = 0.0254 / 100;
  CHECK(image.cols == std::lround(extent.sizes().x() / pitch));
  CHECK(image.rows == std::lround(extent.sizes().y() / pitch));
  // The sheet is the target's own texture: pixels away from edges match it.
  int compared = 0;
  for (int r = 2; r < image.rows; r += 7) {
    for (int c = 3; c < image.cols; c += 7) {
      const std::uint8_t value = image.at<std::uint8_t>(r, c);
      if (value != 0 && value != 255) continue;  // an edge pixel, averaged
      const double x = extent.min().x() + (c + 0.5) * pitch,
                   y = extent.min().y() + (r + 0.5) * pitch;
      CHECK(value == (board->Albedo(x, y) > 0.5 ? 255 : 0));
      ++compared;
    }
  }
  CHECK(compared > 1000);
}

TEST_CASE("target draws a configured AprilGrid; options must fit the type", "[cli][target]") {
  const std::string dir = test::TempDir("target_aprilgrid");
  std::string out;
  REQUIRE(test::RunHandeye("target aprilgrid --tags 3x2 --tag-size 0.04 --tag-spacing 0.3 -o " +
                               dir + "/grid.png",
                           &out) == 0);
  INFO(out);
  const auto target = TargetFromFile(dir + "/grid.json");
  const auto* grid = dynamic_cast<const AprilGridTarget*>(target.get());
  REQUIRE(grid);
  CHECK(grid->tags_x() == 3);
  CHECK(grid->tags_y() == 2);
  CHECK(grid->tag_size_m() == 0.04);
  CHECK(grid->tag_spacing() == 0.3);
  CHECK(grid->border_bits() == 2);
  CHECK(PixelsPerMetre(test::ReadText(dir + "/grid.png")) == 11811);  // 300 dpi

  // The written target object draws the same sheet again.
  REQUIRE(test::RunHandeye("target --target-json " + dir + "/grid.json -o " + dir + "/again.png",
                           &out) == 0);
  CHECK(test::ReadText(dir + "/again.png") == test::ReadText(dir + "/grid.png"));

  const std::vector<std::pair<std::string, std::string>> bad = {
      {"aprilgrid --squares 7x5", "--squares"},
      {"charuco --tags 6x4", "--tags"},
      {"charuco --marker 0.06", "marker_size_m"},
      {"charuco --dictionary DICT_9X9_1", "DICT_5X5_100"},
      {"aprilgrid --border-bits 3", "border_bits"},
      {"aprilgrid --tag-size -1", "--tag-size"},
      {"nosuch", "unknown target type"},
      {"charuco --dpi 5", "--dpi"},
      {"charuco --target-json " + dir + "/grid.json", "--target"},
  };
  for (const auto& [args, message] : bad) {
    INFO(args);
    CHECK(test::RunHandeye("target " + args + " -o " + dir + "/bad.png", &out) == 2);
    CHECK_THAT(out, Catch::Contains(message));
  }
  CHECK_FALSE(fs::exists(dir + "/bad.png"));
}

TEST_CASE("simulate renders ChArUco and AprilGrid cells that calibrate like the checkerboard",
          "[cli][target][simulate]") {
  // Same cell and thresholds as the checkerboard's end-to-end test
  // (calibrate_cli_test.cc): small cell, 3 cameras, 10 poses, 1920x1080.
  for (const std::string type : {"charuco", "aprilgrid"}) {
    INFO(type);
    const std::string dir = test::TempDir("simulate_" + type);
    std::string out;
    REQUIRE(test::RunHandeye("simulate " + dir +
                                 "/sim --cell small --cameras 3 --poses 10 --seed 4 --target " +
                                 type,
                             &out) == 0);
    INFO(out);
    const Dataset dataset = LoadDataset(dir + "/sim/dataset.json");
    CHECK(dataset.target->Type() == type);
    REQUIRE(test::RunHandeye("calibrate " + dir + "/sim/dataset.json -o " + dir + "/result.json",
                             &out) == 0);
    REQUIRE(test::RunHandeye(
                "evaluate " + dir + "/result.json " + dir + "/sim/ground_truth.json --json",
                &out) == 0);
    const nlohmann::json eval = nlohmann::json::parse(out.substr(out.find('{')));
    CHECK(eval["mean_translation_mm"].get<double>() < 5.0);
    CHECK(eval["mean_rotation_deg"].get<double>() < 0.1);
    CHECK(eval["cameras"].size() == 3);
  }
}

TEST_CASE("simulate --target-json takes any target object", "[cli][target][simulate]") {
  const std::string dir = test::TempDir("simulate_target_json");
  test::WriteText(
      dir + "/target.json",
      R"({"type": "aprilgrid", "tagCols": 5, "tagRows": 4, "tagSize": 0.045, "tagSpacing": 0.3})");
  std::string out;
  REQUIRE(test::RunHandeye("simulate " + dir +
                               "/sim --cameras 1 --poses 2 --image-size 640x360 --target-json " +
                               dir + "/target.json",
                           &out) == 0);
  INFO(out);
  const Dataset dataset = LoadDataset(dir + "/sim/dataset.json");
  const auto* grid = dynamic_cast<const AprilGridTarget*>(dataset.target.get());
  REQUIRE(grid);
  CHECK(grid->tags_x() == 5);
  CHECK(grid->tag_size_m() == 0.045);
  CHECK(test::RunHandeye(
            "simulate " + dir + "/sim2 --target-json " + dir + "/target.json --board 7x4", &out) ==
        2);
  CHECK_THAT(out, Catch::Contains("not both"));
}
