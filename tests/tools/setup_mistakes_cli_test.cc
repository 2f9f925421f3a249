// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye calibrate` on a rendered cell set up wrong (issue 24): robot poses
// inverted and every pose listing one image exit 3 naming the mistake and
// its fix; --accept-setup takes the data as they are; the correct cell exits 0.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>

#include "handeye/io/json_util.h"
#include "support/test_support.h"

using namespace handeye;

namespace {

void WriteJson(const nlohmann::json& document, const std::string& path) {
  std::ofstream(path) << document.dump(1);
}

}  // namespace

TEST_CASE("calibrate names setup mistakes on a rendered cell, exit 3; --accept-setup takes them",
          "[cli][calibrate][setup]") {
  const std::string dir = test::TempDir("setup_mistakes_cli");
  std::string out;
  REQUIRE(
      test::RunHandeye("simulate " + dir +
                           "/sim --cell small --cameras 2 --poses 12 --seed 3 --image-size 960x540",
                       &out) == 0);
  // Detect once; the mistakes are made to the dataset's poses and images.
  REQUIRE(test::RunHandeye("calibrate " + dir + "/sim/dataset.json -o " + dir +
                               "/good.json --observations-out " + dir + "/obs.json",
                           &out) == 0);
  INFO(out);

  nlohmann::json inverted = ReadJsonFile(dir + "/obs.json");
  for (auto& pose : inverted["poses"]) {
    Eigen::Matrix4d T;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) T(r, c) = pose["T_base_ee"][r][c].get<double>();
    const Eigen::Matrix4d T_ee_base = T.inverse();
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) pose["T_base_ee"][r][c] = T_ee_base(r, c);
  }
  WriteJson(inverted, dir + "/inverted.json");
  CHECK(test::RunHandeye("calibrate " + dir + "/inverted.json -o " + dir + "/r.json", &out) == 3);
  CHECK(out.find("the robot poses look inverted") != std::string::npos);
  CHECK(out.find("invert every pose") != std::string::npos);
  CHECK(out.find("--accept-setup") != std::string::npos);
  CHECK(test::RunHandeye("calibrate " + dir + "/inverted.json -o " + dir +
                             "/r.json --accept-setup --robot-sigma-mm 0 "
                             "--robot-sigma-deg 0",
                         &out) == 0);

  // Every pose lists the first pose's image of each camera.
  nlohmann::json same = ReadJsonFile(dir + "/sim/dataset.json");
  const nlohmann::json first = same["poses"][0]["images"];
  for (auto& pose : same["poses"]) pose["images"] = first;
  WriteJson(same, dir + "/sim/same_image.json");
  CHECK(test::RunHandeye("calibrate " + dir + "/sim/same_image.json -o " + dir + "/r.json", &out) ==
        3);
  CHECK(out.find("the same image under different robot poses") != std::string::npos);
  CHECK(out.find("all listing the image file") != std::string::npos);
  // Named before detection, by file.
  CHECK(out.find("are one file") != std::string::npos);
}
