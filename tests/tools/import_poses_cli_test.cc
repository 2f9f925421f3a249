// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye import-poses`: a robot pose CSV plus a template become a dataset
// that loads with the poses, in millimetres or metres, and image paths built
// from the ids; bad input exits 2 naming the file and line.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "handeye/io/dataset_json.h"
#include "support/test_support.h"

using namespace handeye;
using Catch::Matchers::Contains;

namespace {

const char kTemplate[] = R"({
  "format": "handeye-dataset/1",
  "setup": "eye_to_hand",
  "target": {"type": "checkerboard", "inner_corners": [7, 4], "square_size_m": 0.04},
  "cameras": [
    {"name": "left", "image_size": [640, 480],
     "intrinsics": {"fx": 500, "fy": 500, "cx": 319.5, "cy": 239.5}, "distortion": {"model": "none"}},
    {"name": "right", "image_size": [640, 480],
     "intrinsics": {"fx": 510, "fy": 510, "cx": 320, "cy": 240}, "distortion": {"model": "none"}}
  ]
})";

}  // namespace

TEST_CASE("import-poses writes a dataset from a CSV pose list and a template", "[cli][import-poses]") {
  const std::string dir = test::TempDir("import_poses_cli");
  test::WriteText(dir + "/template.json", kTemplate);
  test::WriteText(dir + "/robot/poses.csv",
                  "id,x,y,z,qx,qy,qz,qw\n"
                  "0001,400,100,900,0,0,0,1\n"
                  "0002,450.5,-20,880,0,0,0.70710678118654757,0.70710678118654757\n");
  test::WriteText(dir + "/out/images/left/0001.png", "");
  std::string out;
  // --images before POSES: each --images takes one value.
  REQUIRE(test::RunHandeye("import-poses --images left=images/left/{id}.png " + dir + "/robot/poses.csv --template " +
                               dir + "/template.json --translation-unit mm -o " + dir + "/out/dataset.json",
                           &out) == 0);
  INFO(out);
  CHECK_THAT(out, Contains("2 poses"));
  CHECK_THAT(out, Contains("warning: 1 image paths do not exist"));  // 0002.png
  const Dataset d = LoadDataset(dir + "/out/dataset.json");
  REQUIRE(d.poses.size() == 2);
  CHECK(d.cameras.size() == 2);
  CHECK(d.poses[0].id == "0001");
  CHECK((d.poses[0].T_base_ee.translation() - Eigen::Vector3d(0.4, 0.1, 0.9)).norm() < 1e-15);
  CHECK((d.poses[1].T_base_ee.translation() - Eigen::Vector3d(0.4505, -0.02, 0.88)).norm() < 1e-15);
  Eigen::Matrix3d Rz90;
  Rz90 << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  CHECK((d.poses[1].T_base_ee.rotation() - Rz90).cwiseAbs().maxCoeff() < 1e-15);
  CHECK(d.poses[1].images.at("left") == dir + "/out/images/left/0002.png");
  CHECK(d.poses[1].images.count("right") == 0);
  // The template's keys keep their order, the poses come last.
  std::ifstream in(dir + "/out/dataset.json");
  const nlohmann::ordered_json written = nlohmann::ordered_json::parse(in);
  std::vector<std::string> keys;
  for (const auto& item : written.items()) keys.push_back(item.key());
  CHECK(keys == std::vector<std::string>{"format", "setup", "target", "cameras", "poses"});
}

TEST_CASE("import-poses keeps a template's intrinsics files found from the output's folder", "[cli][import-poses]") {
  const std::string dir = test::TempDir("import_poses_cli_intrinsics");
  nlohmann::json templ = nlohmann::json::parse(kTemplate);
  templ["cameras"][0].erase("intrinsics");
  templ["cameras"][0].erase("distortion");
  templ["cameras"][0]["intrinsics_file"] = {{"path", "calib/left.yaml"}, {"format", "ros"}};
  test::WriteText(dir + "/setup/template.json", templ.dump(2));
  test::WriteText(dir + "/setup/calib/left.yaml",
                  "K: [600.5, 0, 320, 0, 601.5, 240, 0, 0, 1]\nD: [0.1, -0.2, 0, 0, 0]\n"
                  "distortion_model: plumb_bob\nwidth: 640\nheight: 480\n");
  test::WriteText(dir + "/poses.csv", "id,x,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0,1\n");
  std::filesystem::create_directories(dir + "/out");
  std::string out;
  REQUIRE(test::RunHandeye("import-poses " + dir + "/poses.csv --template " + dir + "/setup/template.json -o " + dir +
                               "/out/dataset.json",
                           &out) == 0);
  INFO(out);
  const Dataset d = LoadDataset(dir + "/out/dataset.json");
  CHECK(d.cameras[0].fx() == 600.5);
  CHECK(d.cameras[0].Distortion() == std::vector<double>{0.1, -0.2, 0, 0, 0});
  std::ifstream in(dir + "/out/dataset.json");
  CHECK(nlohmann::json::parse(in)["cameras"][0]["intrinsics_file"]["path"] == "../setup/calib/left.yaml");
}

TEST_CASE("import-poses exits 2 on bad input, naming the file and where", "[cli][import-poses]") {
  const std::string dir = test::TempDir("import_poses_cli_errors");
  test::WriteText(dir + "/template.json", kTemplate);
  test::WriteText(dir + "/poses.csv", "id,x,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0,1\n2,0,0,0,0,0,0,2\n");
  std::string out;
  CHECK(test::RunHandeye("import-poses " + dir + "/poses.csv --template " + dir + "/template.json -o " + dir +
                             "/d.json",
                         &out) == 2);
  CHECK_THAT(out, Contains(dir + "/poses.csv: line 3: columns qx,qy,qz,qw: expected a unit quaternion"));

  test::WriteText(dir + "/poses.csv", "id,x,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0,1\n");
  CHECK(test::RunHandeye("import-poses " + dir + "/poses.csv --template " + dir +
                             "/template.json --images middle=x/{id}.png -o " + dir + "/d.json",
                         &out) == 2);
  CHECK_THAT(out, Contains("--images: unknown camera 'middle'; the template's cameras are: left, right"));
  CHECK(test::RunHandeye("import-poses " + dir + "/poses.csv --template " + dir +
                             "/template.json --images left=x.png -o " + dir + "/d.json",
                         &out) == 2);
  CHECK_THAT(out, Contains("with {id} in the pattern"));
  CHECK(test::RunHandeye("import-poses " + dir + "/poses.csv --template " + dir +
                             "/template.json --translation-unit cm -o " + dir + "/d.json",
                         &out) == 2);
  CHECK_THAT(out, Contains("--translation-unit: expected m or mm"));

  nlohmann::json with_poses = nlohmann::json::parse(kTemplate);
  with_poses["poses"] = nlohmann::json::array();
  test::WriteText(dir + "/with_poses.json", with_poses.dump());
  CHECK(test::RunHandeye("import-poses " + dir + "/poses.csv --template " + dir + "/with_poses.json -o " + dir +
                             "/d.json",
                         &out) == 2);
  CHECK_THAT(out, Contains(dir + "/with_poses.json: at /poses: the template must not list poses"));

  nlohmann::json bad_camera = nlohmann::json::parse(kTemplate);
  bad_camera["cameras"][1]["intrinsics"]["fx"] = -1;
  test::WriteText(dir + "/bad_camera.json", bad_camera.dump());
  CHECK(test::RunHandeye("import-poses " + dir + "/poses.csv --template " + dir + "/bad_camera.json -o " + dir +
                             "/d.json",
                         &out) == 2);
  CHECK_THAT(out, Contains(dir + "/bad_camera.json: at /cameras/1/intrinsics/fx: expected a positive number"));
  CHECK_FALSE(std::ifstream(dir + "/d.json").good());
}
