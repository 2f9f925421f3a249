// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye detect`: exit codes and messages (SPEC §7).
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "handeye/detectors/registry.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/json_util.h"
#include "io/io_fixtures.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;

// A dataset with one camera and three poses: two board images and one blank.
// The board drawn has `cols` x `rows` inner corners; the dataset declares
// `declared` (default: the same).
std::string WriteSmallDataset(const std::string& dir, int cols = 5, int rows = 4,
                              std::vector<double> declared = {}) {
  Dataset d;
  TargetSpec spec;
  spec.type = "checkerboard";
  if (declared.empty()) declared = {double(cols), double(rows)};
  spec.values["inner_corners"] = declared;
  spec.values["square_size_m"] = 0.03;
  d.target = MakeTarget(spec);
  std::string why;
  d.cameras.push_back(*Camera::Make("camA", 240, 200, 300, 300, 120, 100, {}, &why));
  for (int p = 0; p < 3; ++p) {
    RobotPose pose;
    pose.id = "p" + std::to_string(p);
    pose.T_base_ee.translation() = Eigen::Vector3d(0.1 * p, 0.2, 0.3);
    pose.images["camA"] = dir + "/images/" + pose.id + ".png";
    test::WriteText(pose.images["camA"], "");
    const cv::Mat image = p == 1 ? cv::Mat(200, 240, CV_8UC1, cv::Scalar(128))
                                 : test::DrawBoard(cols, rows, 24, 40 + 10 * p, 50, 240, 200);
    REQUIRE(cv::imwrite(pose.images["camA"], image));
    d.poses.push_back(pose);
  }
  SaveDataset(d, dir + "/dataset.json");
  return dir + "/dataset.json";
}

TEST_CASE("handeye detect writes observations and a per-camera summary", "[tools][detect]") {
  const std::string dir = test::TempDir("cli_detect");
  const std::string dataset = WriteSmallDataset(dir);
  std::string out;
  REQUIRE(test::RunHandeye("detect '" + dataset + "' -o '" + dir + "/obs.json' --threads 2",
                           &out) == 0);
  CHECK_THAT(out, Contains("camA: 3 images, target found in 2"));
  const Dataset obs = LoadDataset(dir + "/obs.json");
  REQUIRE(obs.observations.size() == 2);
  CHECK(obs.observations[0].pose_id == "p0");
  CHECK(obs.observations[1].pose_id == "p2");
  CHECK(obs.observations[0].ids.size() == 20);
}

TEST_CASE("A board declared the wrong way round: detect warns, calibrate's exit 3 says what to swap",
          "[tools][detect][transposed]") {
  // 5 x 3 inner corners drawn, [3, 5] declared: found in no image today.
  const std::string dir = test::TempDir("cli_detect_transposed");
  const std::string dataset = WriteSmallDataset(dir, 5, 3, {3, 5});
  const std::string hint =
      "target: the board in the images has 5x3 inner corners; the target declares inner_corners "
      "[3, 5]: swap it to [5, 3] (seen in 2 of the 3 images where the target was not found)";
  std::string out;
  REQUIRE(test::RunHandeye("detect '" + dataset + "' -o '" + dir + "/obs.json' --threads 1", &out) == 0);
  CHECK_THAT(out, Contains("camA: 3 images, target found in 0"));
  CHECK_THAT(out, Contains("warning: " + hint));
  CHECK(test::RunHandeye("calibrate '" + dataset + "' -o '" + dir + "/result.json' --threads 1", &out) == 3);
  CHECK_THAT(out, Contains("0 usable views of the target; take at least 3") && Contains("; " + hint));
}

TEST_CASE("handeye detect shows progress on a terminal only, and not with --quiet",
          "[tools][detect][progress]") {
  const std::string dir = test::TempDir("cli_detect_progress");
  const std::string dataset = WriteSmallDataset(dir);
  const std::string detect = "detect '" + dataset + "' -o '" + dir + "/obs.json' --threads 1";
  std::string out;
  SECTION("a terminal: one line redrawn in place, ending with the count, the rate and the time") {
    REQUIRE(test::RunHandeyeOnTerminal(detect, &out) == 0);
    CHECK_THAT(out, Contains("\rdetecting 3/3  "));
    CHECK_THAT(out, Contains("/s  in 0:0"));
    CHECK_THAT(out, Contains("camA: 3 images, target found in 2"));
  }
  SECTION("--quiet on a terminal: no progress, the summary still") {
    REQUIRE(test::RunHandeyeOnTerminal(detect + " --quiet", &out) == 0);
    CHECK_THAT(out, !Contains("detecting"));
    CHECK_THAT(out, Contains("camA: 3 images, target found in 2"));
  }
  SECTION("not a terminal: no progress and no carriage returns") {
    REQUIRE(test::RunHandeye(detect, &out) == 0);
    CHECK_THAT(out, !Contains("detecting"));
    CHECK(out.find('\r') == std::string::npos);
  }
}

TEST_CASE("handeye detect: bad input exits with 2 and says what is wrong", "[tools][detect][bad]") {
  const std::string dir = test::TempDir("cli_detect_bad");
  const std::string dataset = WriteSmallDataset(dir);
  std::string out;

  SECTION("missing dataset file") {
    CHECK(test::RunHandeye("detect '" + dir + "/nope.json' -o '" + dir + "/obs.json'", &out) == 2);
    CHECK_THAT(out, Contains("error: " + dir + "/nope.json: file does not exist"));
  }
  SECTION("a non-rigid robot pose, accepted with --reorthonormalise") {
    nlohmann::json j = nlohmann::json::parse(test::ReadText(dataset));
    j["poses"][1]["T_base_ee"][0][1] = 1e-4;
    test::WriteText(dataset, j.dump(2));
    CHECK(test::RunHandeye("detect '" + dataset + "' -o '" + dir + "/obs.json'", &out) == 2);
    CHECK_THAT(out, Contains(dataset + ": at /poses/1/T_base_ee: expected a rigid 4x4 transform"));
    CHECK_FALSE(std::filesystem::exists(dir + "/obs.json"));
    CHECK(test::RunHandeye("detect '" + dataset + "' -o '" + dir + "/obs.json' --reorthonormalise",
                           &out) == 0);
  }
  SECTION("a missing image") {
    std::filesystem::remove(dir + "/images/p2.png");
    CHECK(test::RunHandeye("detect '" + dataset + "' -o '" + dir + "/obs.json'", &out) == 2);
    CHECK_THAT(out, Contains("error: " + dir + "/images/p2.png: image file does not exist"));
    CHECK_FALSE(std::filesystem::exists(dir + "/obs.json"));
  }
  SECTION("a truncated PNG: our message only, none of libpng's") {
    const std::string image = dir + "/images/p1.png";
    const std::string bytes = test::ReadText(image);
    test::WriteText(image, bytes.substr(0, bytes.size() / 2));
    CHECK(test::RunHandeye("detect '" + dataset + "' -o '" + dir + "/obs.json'", &out) == 2);
    CHECK_THAT(out, Contains("error: " + image + ": damaged PNG: the file ends too early (truncated)"));
    CHECK_THAT(out, !Contains("libpng"));
    CHECK_FALSE(std::filesystem::exists(dir + "/obs.json"));
  }
  SECTION("a PNG whose header claims a huge size: refused from the header") {
    // The IHDR chunk of a 100000 x 100000 and of a 65536 x 65536 image (CRC
    // included) in front of the real file's other chunks.
    const std::string image = dir + "/images/p0.png";
    const std::string real = test::ReadText(image);
    const std::string signature = real.substr(0, 8), rest = real.substr(8 + 25);
    const std::pair<std::uint32_t, std::string> headers[] = {
        {100000, std::string("\x00\x00\x00\x0d" "IHDR" "\x00\x01\x86\xa0\x00\x01\x86\xa0\x08\x00\x00\x00\x00"
                             "\x8d\x39\x54\x14", 25)},
        {65536, std::string("\x00\x00\x00\x0d" "IHDR" "\x00\x01\x00\x00\x00\x01\x00\x00\x08\x00\x00\x00\x00"
                            "\x49\xef\x6f\x3f", 25)}};
    for (const auto& [side, ihdr] : headers) {
      test::WriteText(image, signature + ihdr + rest);
      CHECK(test::RunHandeye("detect '" + dataset + "' -o '" + dir + "/obs.json'", &out) == 2);
      const std::string size = std::to_string(side) + "x" + std::to_string(side);
      CHECK_THAT(out, Contains("error: " + image + ": image is " + size +
                               " but camera 'camA' has image_size [240, 200]"));
    }
  }
  SECTION("an observations file has no images to detect in") {
    REQUIRE(test::RunHandeye("detect '" + dataset + "' -o '" + dir + "/obs.json'", &out) == 0);
    CHECK(test::RunHandeye("detect '" + dir + "/obs.json' -o '" + dir + "/obs2.json'", &out) == 2);
    CHECK_THAT(out, Contains(dir + "/obs.json: at /poses: no images to detect in"));
  }
  SECTION("an output folder that does not exist") {
    CHECK(test::RunHandeye("detect '" + dataset + "' -o '" + dir + "/no/obs.json'", &out) == 2);
    CHECK_THAT(out, Contains("cannot write: folder"));
  }
  SECTION("bad command line") {
    CHECK(test::RunHandeye("detect '" + dataset + "'", &out) == 2);
    CHECK_THAT(out, Contains("--output is required"));
    CHECK(test::RunHandeye("detect '" + dataset + "' -o x.json --threads -1", &out) == 2);
    CHECK_THAT(out, Contains("--threads: expected 0 (all cores) or a positive count"));
    CHECK_THAT(out, Contains("got -1"));
    CHECK(out.size() < 200);  // no 300-digit range
    CHECK(test::RunHandeye("detect '" + dataset + "' -o x.json --threads two", &out) == 2);
    CHECK_THAT(out, Contains("--threads: expected 0 (all cores) or a positive count"));
    CHECK_THAT(out, Contains("got two"));
  }
}

// OpenCV 4.6's FileStorage recursed once per nesting level: an intrinsics
// file of 100 KB nesting its camera_matrix 50 000 deep overflowed the stack
// (exit 139). The same file through the command line, in each of OpenCV's
// three syntaxes: exit 2 naming the file.
TEST_CASE("detect refuses an intrinsics file nested 50 000 deep instead of crashing",
          "[tools][detect][bad]") {
  const std::string dir = test::TempDir("cli_detect_deep");
  const std::string dataset = WriteSmallDataset(dir);
  const auto repeat = [](const std::string& piece, int n) {
    std::string out;
    for (int k = 0; k < n; ++k) out += piece;
    return out;
  };
  constexpr int kDeep = 50000;
  const std::pair<std::string, std::string> files[] = {
      {"flow.yml", "%YAML:1.0\ncamera_matrix: " + repeat("[", kDeep) + "1" + repeat("]", kDeep) + "\n"},
      {"block.yml", "camera_matrix:\n  " + repeat("- ", kDeep) + "1\n"},
      {"deep.json", "{\"camera_matrix\": " + repeat("{\"a\": [", kDeep) + "1" + repeat("]}", kDeep) + "}"},
      {"deep.xml", "<?xml version=\"1.0\"?>\n<opencv_storage>\n<camera_matrix>" + repeat("<_>", kDeep) + "1" +
                       repeat("</_>", kDeep) + "</camera_matrix>\n</opencv_storage>\n"}};
  nlohmann::json d = ReadJsonFile(dataset);
  d["cameras"][0].erase("intrinsics");
  d["cameras"][0].erase("distortion");
  for (const auto& [name, text] : files) {
    INFO(name);
    test::WriteText(dir + "/" + name, text);
    d["cameras"][0]["intrinsics_file"] = {{"path", name}, {"format", "opencv"}};
    test::WriteText(dir + "/deep_dataset.json", d.dump(2));
    std::string out;
    CHECK(test::RunHandeye("detect '" + dir + "/deep_dataset.json' -o '" + dir + "/obs.json'", &out) == 2);
    CHECK_THAT(out, Contains(name + ": nested more than 64 levels deep"));
    CHECK_FALSE(std::filesystem::exists(dir + "/obs.json"));
  }
}

}  // namespace
}  // namespace handeye
