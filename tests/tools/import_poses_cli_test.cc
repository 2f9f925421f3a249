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

// Runs the tests' commands from `dir` for one scope.
class CurrentFolder {
 public:
  explicit CurrentFolder(const std::string& dir) : previous_(std::filesystem::current_path()) {
    std::filesystem::current_path(dir);
  }
  ~CurrentFolder() { std::filesystem::current_path(previous_); }

 private:
  std::filesystem::path previous_;
};

}  // namespace

TEST_CASE("import-poses writes a dataset from a CSV pose list and a template", "[cli][import-poses]") {
  const std::string dir = test::TempDir("import_poses_cli");
  test::WriteText(dir + "/template.json", kTemplate);
  test::WriteText(dir + "/robot/poses.csv",
                  "id,x,y,z,qx,qy,qz,qw\n"
                  "0001,400,100,900,0,0,0,1\n"
                  "0002,450.5,-20,880,0,0,0.70710678118654757,0.70710678118654757\n");
  test::WriteText(dir + "/out/images/left/0001.png", "");
  test::WriteText(dir + "/out/images/left/0002.png", "");
  std::string out;
  // --images before POSES: each --images takes one value. Its paths are
  // relative to the current folder, as on any command line.
  const CurrentFolder in_dir(dir);
  REQUIRE(test::RunHandeye("import-poses --images left=out/images/left/{id}.png " + dir + "/robot/poses.csv --template " +
                               dir + "/template.json --translation-unit mm -o " + dir + "/out/dataset.json",
                           &out) == 0);
  INFO(out);
  CHECK_THAT(out, Contains("2 poses"));
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
  // ... and written relative to the output's folder.
  CHECK(written["poses"][1]["images"]["left"] == "images/left/0002.png");
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

TEST_CASE("import-poses reads rotation vector and Euler CSVs and ROS YAML pose lists", "[cli][import-poses]") {
  const std::string dir = test::TempDir("import_poses_cli_forms");
  test::WriteText(dir + "/template.json", kTemplate);
  // One pose, 90° about z, in every form.
  const double h = std::sqrt(0.5);
  char quaternion[200], rotvec[200], yaml[300];
  std::snprintf(quaternion, sizeof quaternion, "id,x,y,z,qx,qy,qz,qw\n0001,400,100,900,0,0,0,1\n0002,450,-20,880,0,0,%.17g,%.17g\n", h, h);
  std::snprintf(rotvec, sizeof rotvec, "id,x,y,z,rx,ry,rz\n0001,400,100,900,0,0,0\n0002,450,-20,880,0,0,%.17g\n", M_PI / 2);
  std::snprintf(yaml, sizeof yaml,
                "poses:\n- position: {x: 400, y: 100, z: 900}\n  orientation: {x: 0, y: 0, z: 0, w: 1}\n"
                "- position: {x: 450, y: -20, z: 880}\n  orientation: {x: 0, y: 0, z: %.17g, w: %.17g}\n", h, h);
  test::WriteText(dir + "/quaternion.csv", quaternion);
  test::WriteText(dir + "/ur.csv", rotvec);
  test::WriteText(dir + "/kuka.csv", "id,x,y,z,a,b,c\n0001,400,100,900,0,0,0\n0002,450,-20,880,90,0,0\n");
  test::WriteText(dir + "/ros.csv", "id,x,y,z,roll,pitch,yaw\n0001,400,100,900,0,0,0\n0002,450,-20,880,0,0,90\n");
  test::WriteText(dir + "/own.csv", "n,X mm,Y mm,Z mm,A deg,B deg,C deg\n0001,400,100,900,0,0,0\n0002,450,-20,880,90,0,0\n");
  test::WriteText(dir + "/poses.yaml", yaml);
  std::string out;
  REQUIRE(test::RunHandeye("import-poses " + dir + "/quaternion.csv --template " + dir +
                               "/template.json --translation-unit mm -o " + dir + "/expected.json", &out) == 0);
  const Dataset expected = LoadDataset(dir + "/expected.json");
  for (const std::string name : {"ur.csv", "kuka.csv", "ros.csv", "own.csv --rotation kuka_abc", "poses.yaml"}) {
    INFO(name);
    REQUIRE(test::RunHandeye("import-poses " + dir + "/" + name + " --template " + dir +
                                 "/template.json --translation-unit mm -o " + dir + "/d.json", &out) == 0);
    const Dataset d = LoadDataset(dir + "/d.json");
    REQUIRE(d.poses.size() == 2);
    for (int k = 0; k < 2; ++k) {
      CHECK(d.poses[k].id == expected.poses[k].id);
      CHECK((d.poses[k].T_base_ee.matrix() - expected.poses[k].T_base_ee.matrix()).cwiseAbs().maxCoeff() < 1e-12);
    }
  }
  CHECK(test::RunHandeye("import-poses " + dir + "/own.csv --template " + dir + "/template.json -o " + dir + "/d.json",
                         &out) == 2);
  CHECK_THAT(out, Contains(dir + "/own.csv: line 1: expected one of the headers"));
  CHECK(test::RunHandeye("import-poses " + dir + "/own.csv --rotation euler --template " + dir + "/template.json -o " +
                             dir + "/d.json", &out) == 2);
  CHECK_THAT(out, Contains("--rotation: expected quaternion, rotvec, kuka_abc or rpy, got 'euler'"));
}

TEST_CASE("import-poses refuses a reach that says the unit is wrong, naming --translation-unit", "[cli][import-poses]") {
  const std::string dir = test::TempDir("import_poses_cli_units");
  test::WriteText(dir + "/template.json", kTemplate);
  test::WriteText(dir + "/mm.csv", "id,x,y,z,qx,qy,qz,qw\n1,400,100,900,0,0,0,1\n2,450,-20,880,0,0,0,1\n");
  test::WriteText(dir + "/m.csv", "id,x,y,z,qx,qy,qz,qw\n1,0.4,0.1,0.9,0,0,0,1\n2,0.45,-0.02,0.88,0,0,0,1\n");
  std::string out;
  CHECK(test::RunHandeye("import-poses " + dir + "/mm.csv --template " + dir + "/template.json -o " + dir + "/d.json",
                         &out) == 2);
  CHECK_THAT(out, Contains(dir + "/mm.csv: pose '1' (line 2) is 989.9 m from the robot base"));
  CHECK_THAT(out, Contains("if they are millimetres, use --translation-unit mm"));
  CHECK(test::RunHandeye("import-poses " + dir + "/m.csv --translation-unit mm --template " + dir +
                             "/template.json -o " + dir + "/d.json", &out) == 2);
  CHECK_THAT(out, Contains(dir + "/m.csv: every pose is within 10 mm of the robot base"));
  CHECK_THAT(out, Contains("if they are metres, use --translation-unit m"));
  CHECK_FALSE(std::filesystem::exists(dir + "/d.json"));
  CHECK(test::RunHandeye("import-poses " + dir + "/m.csv --template " + dir + "/template.json -o " + dir + "/d.json",
                         &out) == 0);
}

TEST_CASE("import-poses exits 2 naming an --images file that does not exist", "[cli][import-poses]") {
  const std::string dir = test::TempDir("import_poses_cli_images");
  test::WriteText(dir + "/template.json", kTemplate);
  test::WriteText(dir + "/poses.csv", "id,x,y,z,qx,qy,qz,qw\n0001,0.4,0.1,0.9,0,0,0,1\n0002,0.45,0,0.9,0,0,0,1\n");
  test::WriteText(dir + "/shots/left/0001.png", "");
  test::WriteText(dir + "/shots/right/0001.png", "");
  test::WriteText(dir + "/shots/right/0002.png", "");
  // The output's folder exists: the missing image is what is wrong here.
  std::filesystem::create_directories(dir + "/out");
  const CurrentFolder in_dir(dir);
  std::string out;
  CHECK(test::RunHandeye("import-poses poses.csv --template template.json --images left=shots/left/{id}.png "
                         "--images right=shots/right/{id}.png -o out/d.json",
                         &out) == 2);
  CHECK_THAT(out, Contains("shots/left/0002.png: image file does not exist (camera 'left', pose '0002', from "
                           "--images left=shots/left/{id}.png; 1 of 4 images are missing; --images paths are "
                           "relative to the current folder)"));
  CHECK_FALSE(std::filesystem::exists(dir + "/out/d.json"));
  test::WriteText(dir + "/shots/left/0002.png", "");
  REQUIRE(test::RunHandeye("import-poses poses.csv --template template.json --images left=shots/left/{id}.png "
                           "--images right=" + dir + "/shots/right/{id}.png -o out/d.json",
                           &out) == 0);
  const Dataset d = LoadDataset(dir + "/out/d.json");
  CHECK(d.poses[1].images.at("left") == dir + "/shots/left/0002.png");
  CHECK(d.poses[1].images.at("right") == dir + "/shots/right/0002.png");
}
