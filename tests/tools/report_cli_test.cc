// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye report` and `handeye calibrate --report` end to end on a rendered
// cell (every linked file of the page exists and decodes), and the exit codes
// for bad input.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <sstream>

#include "support/test_support.h"

namespace {

using Catch::Matchers::Contains;

std::string Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Checks that every src/href of DIR/index.html names a file in DIR that
// OpenCV decodes; returns how many it checked.
int CheckLinks(const std::string& dir) {
  const std::string html = Read(dir + "/index.html");
  REQUIRE(!html.empty());
  const std::regex link(R"((?:src|href)=\"([^\"]*)\")");
  int checked = 0;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), link); it != std::sregex_iterator();
       ++it) {
    const std::string target = (*it)[1];
    INFO(target);
    CHECK(target.find(':') == std::string::npos);  // no URL scheme: nothing from the network
    CHECK(target.find("..") == std::string::npos);
    CHECK(!cv::imread(dir + "/" + target, cv::IMREAD_UNCHANGED).empty());
    ++checked;
  }
  return checked;
}

TEST_CASE("report and calibrate --report on a rendered 4-camera cell", "[cli][report]") {
  const std::string dir = handeye::test::TempDir("report_cli");
  std::string out;
  REQUIRE(handeye::test::RunHandeye(
              "simulate " + dir +
                  "/sim --cell small --cameras 4 --poses 6 --seed 7 --image-size 960x540",
              &out) == 0);
  INFO(out);
  REQUIRE(handeye::test::RunHandeye("calibrate " + dir + "/sim/dataset.json -o " + dir +
                                        "/result.json --report " + dir + "/from_calibrate",
                                    &out) == 0);
  CHECK_THAT(out, Contains("from_calibrate/index.html"));
  CHECK(CheckLinks(dir + "/from_calibrate") > 20);

  // The report subcommand, with the detections given as an observations file.
  REQUIRE(handeye::test::RunHandeye("detect " + dir + "/sim/dataset.json -o " + dir + "/obs.json",
                                    &out) == 0);
  REQUIRE(handeye::test::RunHandeye("report " + dir + "/sim/dataset.json " + dir +
                                        "/result.json -o " + dir + "/report --observations " + dir +
                                        "/obs.json --threads 2",
                                    &out) == 0);
  CHECK_THAT(out, Contains("wrote") && Contains("overlays"));
  CHECK(CheckLinks(dir + "/report") > 20);
  // The same overlays as from calibrate: same data (JSON round-trips
  // doubles exactly), same drawing.
  int compared = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(dir + "/report/overlays")) {
    if (!entry.is_regular_file()) continue;
    const std::string relative = std::filesystem::relative(entry.path(), dir + "/report").string();
    INFO(relative);
    const cv::Mat a = cv::imread(entry.path().string()),
                  b = cv::imread(dir + "/from_calibrate/" + relative);
    REQUIRE(a.size() == b.size());
    CHECK(cv::norm(a, b, cv::NORM_INF) == 0);
    ++compared;
  }
  CHECK(compared > 5);
}

TEST_CASE("report exits 2 on bad input", "[cli][report]") {
  const std::string dir = handeye::test::TempDir("report_cli_errors");
  std::string out;
  REQUIRE(handeye::test::RunHandeye(
              "simulate " + dir +
                  "/sim --cell small --cameras 2 --poses 6 --seed 3 --image-size 640x360",
              &out) == 0);
  REQUIRE(handeye::test::RunHandeye("detect " + dir + "/sim/dataset.json -o " + dir + "/obs.json",
                                    &out) == 0);
  REQUIRE(handeye::test::RunHandeye("calibrate " + dir + "/obs.json -o " + dir + "/result.json",
                                    &out) == 0);

  CHECK(handeye::test::RunHandeye(
            "report " + dir + "/obs.json " + dir + "/missing.json -o " + dir + "/r", &out) == 2);
  CHECK_THAT(out, Contains("missing.json"));

  // A result whose camera is not in the dataset: the error names the result file.
  std::string result = Read(dir + "/result.json");
  const auto at = result.find("\"cam1\"");
  REQUIRE(at != std::string::npos);
  result.replace(at, 6, "\"camZ\"");
  handeye::test::WriteText(dir + "/other.json", result);
  CHECK(handeye::test::RunHandeye(
            "report " + dir + "/obs.json " + dir + "/other.json -o " + dir + "/r", &out) == 2);
  CHECK_THAT(out, Contains("other.json") && Contains("cam1"));

  // The report folder cannot be created under a file.
  handeye::test::WriteText(dir + "/file", "x");
  CHECK(handeye::test::RunHandeye(
            "report " + dir + "/obs.json " + dir + "/result.json -o " + dir + "/file/r", &out) ==
        2);
  CHECK_THAT(out, Contains("file/r"));

  // Observations only, no images: overlays on a neutral canvas, exit 0.
  CHECK(handeye::test::RunHandeye(
            "report " + dir + "/obs.json " + dir + "/result.json -o " + dir + "/r", &out) == 0);
  CHECK(CheckLinks(dir + "/r") > 10);
}

}  // namespace
