// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye export`: each format is written for a result file, frame names
// are options, and bad input exits 2 naming what is wrong. The formats' exact
// content is tested in tests/io/export_test.cc.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

#include "handeye/core/transform.h"
#include "handeye/io/result_json.h"
#include "handeye/io/yaml_file.h"
#include "support/test_support.h"

using namespace handeye;
using Catch::Matchers::Contains;

namespace {

std::string WriteResult(const std::string& dir) {
  CalibrationResult r;
  r.setup = Setup::kEyeToHand;
  CameraResult cam;
  cam.name = "cam0";
  cam.calibrated = true;
  cam.T_cam = MakeTransformFromRotationVector({2.0, -0.4, 0.3}, {-1.2, 1.9, 1.15});
  CameraResult blind;
  blind.name = "cam1";
  r.cameras = {cam, blind};
  r.T_target = MakeTransformFromRotationVector({0.1, 0.2, 0.3}, {0.01, 0.02, 0.1});
  SaveResult(r, dir + "/result.json");
  return dir + "/result.json";
}

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST_CASE("export writes every format, with the frame names asked for", "[cli][export]") {
  const std::string dir = test::TempDir("export_cli");
  const std::string result = WriteResult(dir);
  std::string out;
  for (const std::string format : {"ros2-launch", "urdf", "tf-static-yaml", "opencv-yaml"}) {
    INFO(format);
    REQUIRE(test::RunHandeye("export " + result + " --to " + format + " -o " + dir + "/out." + format, &out) == 0);
    CHECK_THAT(out, Contains("warning: camera 'cam1' was not calibrated; not exported"));
    CHECK_THAT(Slurp(dir + "/out." + format), Contains("cam0_optical_frame"));
  }
  REQUIRE(test::RunHandeye("export " + result + " --to tf-static-yaml --base-frame world --ee-frame flange -o " +
                               dir + "/tf.yaml",
                           &out) == 0);
  const nlohmann::json tf = ReadYamlFile(dir + "/tf.yaml");
  REQUIRE(tf["transforms"].size() == 3);
  CHECK(tf["transforms"][0]["header"]["frame_id"] == "world");
  CHECK(tf["transforms"][2]["header"]["frame_id"] == "flange");
}

TEST_CASE("export exits 2 on bad input", "[cli][export]") {
  const std::string dir = test::TempDir("export_cli_errors");
  const std::string result = WriteResult(dir);
  std::string out;
  CHECK(test::RunHandeye("export " + result + " --to sdf -o " + dir + "/x", &out) == 2);
  CHECK_THAT(out, Contains("--to: expected one of ros2-launch, urdf, tf-static-yaml, opencv-yaml"));
  CHECK(test::RunHandeye("export " + result + " --to urdf --base-frame 'my base' -o " + dir + "/x", &out) == 2);
  CHECK_THAT(out, Contains("base frame 'my base' is not a frame name"));
  CHECK(test::RunHandeye("export " + dir + "/missing.json --to urdf -o " + dir + "/x", &out) == 2);
  CHECK_THAT(out, Contains(dir + "/missing.json: file does not exist"));
  CHECK(test::RunHandeye("export " + result + " --to urdf -o " + dir + "/no/such/folder/x.urdf", &out) == 2);
  CHECK_THAT(out, Contains("no/such/folder"));
}

TEST_CASE("export --camera-frame names the optical frame; --optical-only drops the camera link",
          "[cli][export]") {
  const std::string dir = test::TempDir("export_cli_camera_frame");
  const std::string result = WriteResult(dir);
  std::string out;
  for (const std::string format : {"ros2-launch", "urdf", "tf-static-yaml", "opencv-yaml"}) {
    INFO(format);
    const std::string linked = dir + "/linked." + format, optical = dir + "/optical." + format;
    // OpenCV YAML names no frames but the optical one; its body-frame matrix is a key.
    const std::string link = format == "opencv-yaml" ? "T_base_cam_link" : "cam0_link";
    REQUIRE(test::RunHandeye("export " + result + " --to " + format +
                                 " --camera-frame cam0=camera_color_optical_frame -o " + linked,
                             &out) == 0);
    CHECK_THAT(Slurp(linked), Contains("camera_color_optical_frame"));
    CHECK_THAT(Slurp(linked), Contains(link));
    CHECK_THAT(Slurp(linked), !Contains("cam0_optical_frame"));
    REQUIRE(test::RunHandeye("export " + result + " --to " + format +
                                 " --optical-only --camera-frame cam0=camera_color_optical_frame -o " + optical,
                             &out) == 0);
    CHECK_THAT(out, Contains("as optical frames only"));
    CHECK_THAT(Slurp(optical), Contains("camera_color_optical_frame"));
    CHECK_THAT(Slurp(optical), !Contains(link));
  }
  // tf_static: one transform per camera, straight from the base, plus the target.
  const nlohmann::json tf = ReadYamlFile(dir + "/optical.tf-static-yaml");
  REQUIRE(tf["transforms"].size() == 2);
  CHECK(tf["transforms"][0]["header"]["frame_id"] == "base_link");
  CHECK(tf["transforms"][0]["child_frame_id"] == "camera_color_optical_frame");
  const auto& t = tf["transforms"][0]["transform"]["translation"];
  CHECK(std::abs(t["x"].get<double>() - -1.2) < 1e-12);
  CHECK(std::abs(t["y"].get<double>() - 1.9) < 1e-12);
  CHECK(std::abs(t["z"].get<double>() - 1.15) < 1e-12);
}

TEST_CASE("export exits 2 on a bad --camera-frame, naming the flag", "[cli][export]") {
  const std::string dir = test::TempDir("export_cli_camera_frame_errors");
  const std::string result = WriteResult(dir);
  const std::string run = "export " + result + " --to tf-static-yaml -o " + dir + "/x.yaml --camera-frame ";
  const std::pair<std::string, std::string> cases[] = {
      {"cam0", "--camera-frame 'cam0': expected CAMERA=FRAME"},
      {"=camera_color_optical_frame", "the camera name before '=' is empty"},
      {"cam0=", "--camera-frame 'cam0=': the frame name after '=' is empty"},
      {"'cam0=color frame'", "--camera-frame 'cam0=color frame': frame 'color frame' of camera 'cam0' is not a frame name"},
      {"cam9=camera_color_optical_frame",
       "--camera-frame 'cam9=camera_color_optical_frame': " + result + " has no camera 'cam9' (its cameras: cam0, cam1)"},
      {"cam0=a --camera-frame cam0=b", "--camera-frame 'cam0=b': camera 'cam0' is given a frame twice"},
      {"cam0=a --camera-frame cam1=a", "--camera-frame 'cam1=a': frame 'a' is already given to camera 'cam0'"},
      {"cam0=base_link", "frame 'base_link' is the name of a robot or target frame"},
  };
  for (const auto& [value, message] : cases) {
    INFO(value);
    std::string out;
    CHECK(test::RunHandeye(run + value, &out) == 2);
    CHECK_THAT(out, Contains(message));
  }
  std::ifstream written(dir + "/x.yaml");
  CHECK_FALSE(written.good());
}
