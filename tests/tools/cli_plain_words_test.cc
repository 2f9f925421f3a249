// SPDX-License-Identifier: GPL-2.0-or-later
// Small things a new user runs into, each said in the user's terms: files in
// the wrong order, --version, absurd --threads, options that do not go
// together, a pose rounded off rigid, raw doubles in notes, a corner outside
// its image, and intrinsics that fit no view.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "handeye/io/dataset_json.h"
#include "projected_cell.h"
#include "support/test_support.h"

using namespace handeye;
using Catch::Matchers::Contains;

namespace {

// CalibratedSmallCell with its ground truth in DIR/truth.json.
std::string MakeCalibratedCell(const std::string& dir) {
  SaveGroundTruth(test::ProjectedSmallCell(8).truth, dir + "/truth.json");
  return test::CalibratedSmallCell(dir);
}

// DIR/obs.json changed by `edit`, saved as DIR/NAME.
std::string Edited(const std::string& dir, const std::string& name, void (*edit)(nlohmann::json*)) {
  nlohmann::json obs = nlohmann::json::parse(test::ReadText(dir + "/obs.json"));
  edit(&obs);
  test::WriteText(dir + "/" + name, obs.dump());
  return dir + "/" + name;
}

// Numbers with six or more significant digits, as a double printed raw has.
std::vector<std::string> RawDoubles(const std::string& line) {
  std::vector<std::string> raw;
  const std::regex number(R"(\d+\.\d+)");
  for (auto it = std::sregex_iterator(line.begin(), line.end(), number);
       it != std::sregex_iterator(); ++it) {
    std::string digits = std::regex_replace(it->str(), std::regex(R"(\.)"), "");
    digits.erase(0, digits.find_first_not_of('0'));
    if (digits.size() >= 6) raw.push_back(it->str());
  }
  return raw;
}

}  // namespace

TEST_CASE("files given in the wrong order get the expected order", "[cli][plain]") {
  const std::string dir = test::TempDir("plain_order_cli");
  MakeCalibratedCell(dir);
  const std::string obs = dir + "/obs.json", result = dir + "/result.json",
                    truth = dir + "/truth.json";
  std::string out;
  CHECK(test::RunHandeye("check " + obs + " " + result, &out) == 2);
  CHECK_THAT(out, Contains("the order is `handeye check RESULT DATASET|OBS`"));
  CHECK(test::RunHandeye("evaluate " + truth + " " + result, &out) == 2);
  CHECK_THAT(out, Contains("the order is `handeye evaluate RESULT GROUND_TRUTH`"));
  CHECK(test::RunHandeye("report " + result + " " + obs + " -o " + dir + "/rep", &out) == 2);
  CHECK_THAT(out, Contains("the order is `handeye report DATASET RESULT -o DIR`"));
  CHECK(test::RunHandeye("evaluate " + result + " " + truth, &out) == 0);
}

TEST_CASE("--version, and --threads within reason", "[cli][plain]") {
  std::string out;
  CHECK(test::RunHandeye("--version", &out) == 0);
  CHECK_THAT(out, Contains("handeye 1."));
  CHECK(test::RunHandeye("detect x.json -o y.json --threads 100000", &out) == 2);
  CHECK_THAT(out, Contains("--threads: expected 0 (all cores) or a positive count up to"));
  CHECK(test::RunHandeye("calibrate x.json -o y.json --threads 1025", &out) == 2);
}

TEST_CASE("calibrate options that do not go together are named as flags", "[cli][plain]") {
  const std::string dir = test::TempDir("plain_options_cli");
  MakeCalibratedCell(dir);
  const std::string calibrate = "calibrate " + dir + "/obs.json -o " + dir + "/r.json ";
  std::string out;
  CHECK(test::RunHandeye(calibrate + "--cross-validate --method park", &out) == 2);
  CHECK_THAT(out, Contains("--cross-validate"));
  CHECK_THAT(out, Contains("--method joint"));
  CHECK(test::RunHandeye(calibrate + "--robot-sigma-mm 1", &out) == 2);
  CHECK_THAT(
      out,
      Contains(
          "--robot-sigma-mm given alone: give --robot-sigma-mm and --robot-sigma-deg together"));
  CHECK_THAT(out, !Contains("robot_sigma_mm"));
  CHECK(test::RunHandeye(calibrate + "--robot-sigma-mm 0 --robot-sigma-deg 0.1", &out) == 2);
  CHECK_THAT(out, Contains("0 means an exact robot"));
}

TEST_CASE(
    "a rounded pose, a corner outside the image and absurd distortion are named for what they are",
    "[cli][plain]") {
  const std::string dir = test::TempDir("plain_data_cli");
  const std::string calibrated = MakeCalibratedCell(dir);
  std::istringstream lines(calibrated);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("note:", 0) == 0 || line.rfind("warning:", 0) == 0) {
      INFO(line);
      CHECK(RawDoubles(line).empty());
    }
  std::string out;

  const std::string off_rigid = Edited(dir, "off_rigid.json", [](nlohmann::json* obs) {
    auto& T = (*obs)["poses"][0]["T_base_ee"];
    T[0][0] = T[0][0].get<double>() + 1.8e-5;
  });
  CHECK(test::RunHandeye("calibrate " + off_rigid + " -o " + dir + "/r.json", &out) == 2);
  CHECK_THAT(out, Contains("/poses/0/T_base_ee"));
  CHECK_THAT(out, Contains("--reorthonormalise"));
  CHECK(test::RunHandeye("calibrate " + off_rigid + " -o " + dir + "/r.json --reorthonormalise -q",
                         &out) == 0);

  const std::string far = Edited(dir, "far.json", [](nlohmann::json* obs) {
    (*obs)["observations"][0]["points_px"][0] = {1e7, -5e6};
  });
  CHECK(test::RunHandeye("calibrate " + far + " -o " + dir + "/r.json", &out) == 2);
  CHECK_THAT(out, Contains("/observations/0/points_px/0"));
  CHECK_THAT(out, Contains("this observation is wrong, not the robot pose"));

  const std::string k1_cam1 = Edited(dir, "k1_cam1.json", [](nlohmann::json* obs) {
    (*obs)["cameras"][1]["distortion"]["coeffs"][0] = 50.0;
  });
  CHECK(test::RunHandeye("calibrate " + k1_cam1 + " -o " + dir + "/r.json -q", &out) == 0);
  CHECK_THAT(out, Contains("camera 'cam1': the target was detected in"));
  CHECK_THAT(out, Contains("intrinsics and distortion: these look wrong"));
  CHECK_THAT(out, !Contains("never saw the target"));
  const std::string k1_all = Edited(dir, "k1_all.json", [](nlohmann::json* obs) {
    for (auto& camera : (*obs)["cameras"]) camera["distortion"]["coeffs"][0] = 50.0;
  });
  CHECK(test::RunHandeye("calibrate " + k1_all + " -o " + dir + "/r.json -q", &out) == 3);
  CHECK_THAT(out, Contains("check fx, fy, cx, cy and the distortion coefficients"));
}
