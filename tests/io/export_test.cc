// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye export` formats (io/export.h): each output is parsed back the way
// its consumer reads it and every transform compared with the result to
// 1e-9, including a camera whose body frame is at gimbal lock for URDF's rpy.
#include "handeye/io/export.h"

#include <catch2/catch.hpp>
#include <map>
#include <opencv2/core.hpp>
#include <random>
#include <regex>
#include <set>
#include <sstream>

#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "handeye/io/yaml_file.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;

constexpr double kParseBackTolerance = 1e-9;

Eigen::Matrix3d FromRpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Isometry3d FromRotation(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

// cam0: a general pose; cam1: its body frame pitched by exactly 90° (URDF rpy
// at gimbal lock); cam2: pitched 1e-7 rad short of it; cam3: not calibrated.
CalibrationResult SampleResult(Setup setup) {
  CalibrationResult r;
  r.setup = setup;
  r.method = Method::kJoint;
  auto camera = [](const std::string& name, const Eigen::Isometry3d& T_parent_link) {
    CameraResult c;
    c.name = name;
    c.calibrated = true;
    c.T_cam = T_parent_link * OpticalInLink();  // T_parent_optical
    return c;
  };
  r.cameras.push_back(camera("cam0", MakeTransformFromRotationVector({0.3, -2.2, 0.1}, {1.9, -1.8, 1.9})));
  r.cameras.push_back(camera("cam1", FromRotation(FromRpy(0.3, M_PI / 2, -1.1), {-1.234567890123, 0.5, 2.75})));
  r.cameras.push_back(camera("cam2", FromRotation(FromRpy(-2.0, M_PI / 2 - 1e-7, 0.7), {0.1, 1e-12, -3.0})));
  CameraResult skipped;
  skipped.name = "cam3";
  r.cameras.push_back(skipped);
  r.T_target = MakeTransformFromRotationVector({0.1, 0.2, 0.3}, {0.01, 0.02, 0.1});
  return r;
}

struct Parsed {
  std::string parent;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
};
using ParsedTransforms = std::map<std::string, Parsed>;  // by child frame

double Parse(const std::string& text) {
  std::size_t used = 0;
  const double x = std::stod(text, &used);
  REQUIRE(used == text.size());
  return x;
}

Eigen::Isometry3d FromQuaternion(double x, double y, double z, double qx, double qy, double qz, double qw) {
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  REQUIRE(std::abs(q.norm() - 1) < 1e-15);
  REQUIRE(qw >= 0);
  return FromRotation(q.toRotationMatrix(), {x, y, z});
}

ParsedTransforms ParseLaunch(const std::string& text) {
  ParsedTransforms out;
  const std::regex node(R"(executable='static_transform_publisher',[\s\S]*?arguments=\[([^\]]*)\])");
  const std::regex token(R"('([^']*)')");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), node); it != std::sregex_iterator(); ++it) {
    const std::string args = (*it)[1];
    std::vector<std::string> tokens;
    for (auto t = std::sregex_iterator(args.begin(), args.end(), token); t != std::sregex_iterator(); ++t)
      tokens.push_back((*t)[1]);
    REQUIRE(tokens.size() == 18);
    std::map<std::string, std::string> value;
    for (std::size_t i = 0; i + 1 < tokens.size(); i += 2) value[tokens[i]] = tokens[i + 1];
    for (const char* flag : {"--x", "--y", "--z", "--qx", "--qy", "--qz", "--qw", "--frame-id", "--child-frame-id"})
      REQUIRE(value.count(flag));
    out[value["--child-frame-id"]] = {
        value["--frame-id"], FromQuaternion(Parse(value["--x"]), Parse(value["--y"]), Parse(value["--z"]),
                                            Parse(value["--qx"]), Parse(value["--qy"]), Parse(value["--qz"]),
                                            Parse(value["--qw"]))};
  }
  return out;
}

std::vector<double> Numbers(const std::string& text) {
  std::vector<double> out;
  std::istringstream in(text);
  std::string word;
  while (in >> word) out.push_back(Parse(word));
  return out;
}

ParsedTransforms ParseUrdf(const std::string& text) {
  // XML forbids "--" inside a comment; a URDF parser would reject the file.
  const std::regex comment(R"(<!--([\s\S]*?)-->)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), comment); it != std::sregex_iterator(); ++it)
    CHECK((*it)[1].str().find("--") == std::string::npos);
  ParsedTransforms out;
  const std::regex joint(
      R"re(<joint name="([^"]+)" type="fixed">\s*<parent link="([^"]+)"/>\s*<child link="([^"]+)"/>\s*<origin xyz="([^"]+)" rpy="([^"]+)"/>\s*</joint>)re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), joint); it != std::sregex_iterator(); ++it) {
    const std::vector<double> xyz = Numbers((*it)[4]);
    const std::vector<double> rpy = Numbers((*it)[5]);
    REQUIRE(xyz.size() == 3);
    REQUIRE(rpy.size() == 3);
    out[(*it)[3]] = {(*it)[2], FromRotation(FromRpy(rpy[0], rpy[1], rpy[2]), {xyz[0], xyz[1], xyz[2]})};
  }
  return out;
}

ParsedTransforms ParseTfStatic(const std::string& text) {
  const nlohmann::json doc = ParseYaml(text, "tf_static.yaml");
  ParsedTransforms out;
  for (const auto& tf : doc.at("transforms")) {
    const auto& t = tf.at("transform").at("translation");
    const auto& q = tf.at("transform").at("rotation");
    CHECK(tf.at("header").at("stamp").at("sec") == 0);
    out[tf.at("child_frame_id").get<std::string>()] = {
        tf.at("header").at("frame_id").get<std::string>(),
        FromQuaternion(t.at("x"), t.at("y"), t.at("z"), q.at("x"), q.at("y"), q.at("z"), q.at("w"))};
  }
  return out;
}

Eigen::Isometry3d ReadMatrix4(const cv::FileNode& node) {
  cv::Mat M;
  node >> M;
  REQUIRE(M.rows == 4);
  REQUIRE(M.cols == 4);
  REQUIRE(M.type() == CV_64F);
  Eigen::Matrix4d E;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) E(r, c) = M.at<double>(r, c);
  CHECK(E.row(3) == Eigen::RowVector4d(0, 0, 0, 1));
  Eigen::Isometry3d T;
  T.matrix() = E;
  return T;
}

void CheckClose(const Eigen::Isometry3d& got, const Eigen::Isometry3d& expected, const std::string& what) {
  INFO(what << "\ngot\n" << got.matrix() << "\nexpected\n" << expected.matrix());
  CHECK((got.matrix() - expected.matrix()).cwiseAbs().maxCoeff() <= kParseBackTolerance);
}

std::string OpticalFrame(const std::string& camera, const ExportOptions& frames) {
  const auto named = frames.camera_frames.find(camera);
  return named == frames.camera_frames.end() ? camera + "_optical_frame" : named->second;
}

// Transforms per calibrated camera of SampleResult (3 of them) under `frames`.
std::size_t CameraTransforms(const ExportOptions& frames) { return frames.optical_only ? 3 : 6; }

// The parsed transforms are exactly the result's chain.
void CheckTransforms(const ParsedTransforms& parsed, const CalibrationResult& result, const ExportOptions& frames) {
  const bool to_hand = result.setup == Setup::kEyeToHand;
  const std::string parent = to_hand ? frames.base_frame : frames.ee_frame;
  CHECK(parsed.size() == CameraTransforms(frames) + 1);  // + the target
  for (const CameraResult& camera : result.cameras) {
    const std::string link = camera.name + "_link", optical = OpticalFrame(camera.name, frames);
    if (!camera.calibrated || frames.optical_only) CHECK(parsed.count(link) == 0);
    if (!camera.calibrated) {
      CHECK(parsed.count(optical) == 0);
      continue;
    }
    REQUIRE(parsed.count(optical));
    if (frames.optical_only) {
      // One transform: the robot frame straight to the calibrated optical frame.
      CHECK(parsed.at(optical).parent == parent);
      CheckClose(parsed.at(optical).T, camera.T_cam, parent + " -> " + optical);
      continue;
    }
    REQUIRE(parsed.count(link));
    CHECK(parsed.at(link).parent == parent);
    CHECK(parsed.at(optical).parent == link);
    CheckClose(parsed.at(link).T * parsed.at(optical).T, camera.T_cam, parent + " -> " + optical);
    CheckClose(parsed.at(optical).T, OpticalInLink(), link + " -> " + optical);
  }
  REQUIRE(parsed.count(frames.target_frame));
  CHECK(parsed.at(frames.target_frame).parent == (to_hand ? frames.ee_frame : frames.base_frame));
  CheckClose(parsed.at(frames.target_frame).T, result.T_target, "target");
}

TEST_CASE("The optical frame in the camera link: REP-103's fixed rotation", "[io][export]") {
  const Eigen::Isometry3d T = OpticalInLink();
  // Optical z (forward) is link x, optical x (right) is link -y, optical y (down) is link -z.
  CHECK(T.rotation() * Eigen::Vector3d::UnitZ() == Eigen::Vector3d::UnitX());
  CHECK(T.rotation() * Eigen::Vector3d::UnitX() == -Eigen::Vector3d::UnitY());
  CHECK(T.rotation() * Eigen::Vector3d::UnitY() == -Eigen::Vector3d::UnitZ());
  CHECK(T.translation() == Eigen::Vector3d::Zero());
  const Eigen::Vector3d rpy = RollPitchYaw(T.rotation());
  CHECK(rpy.isApprox(Eigen::Vector3d(-M_PI / 2, 0, -M_PI / 2), 1e-15));
  const Eigen::Quaterniond q(T.rotation());
  const double sign = q.w() < 0 ? -1 : 1;
  CHECK((sign * q.coeffs() - Eigen::Vector4d(-0.5, 0.5, -0.5, 0.5)).norm() < 1e-15);
}

// The frame layouts a user can ask for: the default, a driver's name for one
// optical frame, and optical frames only (one of them named).
std::vector<std::pair<std::string, ExportOptions>> FrameLayouts() {
  ExportOptions named;
  named.camera_frames["cam0"] = "camera_color_optical_frame";
  ExportOptions optical_only = named;
  optical_only.optical_only = true;
  return {{"default frames", ExportOptions{}}, {"cam0 optical frame named", named}, {"optical frames only", optical_only}};
}

TEST_CASE("Every export format parses back to the result's transforms to 1e-9", "[io][export]") {
  for (const auto& [layout, frames] : FrameLayouts()) {
    for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
      INFO(layout << ", " << SetupName(setup));
      const CalibrationResult result = SampleResult(setup);
      std::vector<Warning> warnings;
      const std::string launch = FormatExport(result, ExportFormat::kRos2Launch, frames, "result.json", &warnings);
      REQUIRE(warnings.size() == 1);
      CHECK_THAT(warnings[0].text, Contains("camera 'cam3' was not calibrated; not exported"));
      CHECK(warnings[0].kind == WarningKind::kCameraNotExported);
      CHECK(warnings[0].camera == "cam3");
      CHECK_THAT(launch, Contains("from launch_ros.actions import Node"));
      CheckTransforms(ParseLaunch(launch), result, frames);

      const std::string urdf = FormatExport(result, ExportFormat::kUrdf, frames, "result.json");
      CHECK_THAT(urdf, Contains("<robot name=\"handeye_calibration\">"));
      CheckTransforms(ParseUrdf(urdf), result, frames);
      // Outside comments the URDF is one tree: every link but the root is the
      // child of one joint whose parent is a link of the file. The target's
      // joint, whose parent is elsewhere in the robot, is only in a comment.
      const std::string live = std::regex_replace(urdf, std::regex(R"(<!--[\s\S]*?-->)"), "");
      const ParsedTransforms joints = ParseUrdf(live);
      CHECK(joints.size() == CameraTransforms(frames));
      CHECK(joints.count(frames.target_frame) == 0);
      std::set<std::string> links;
      const std::regex link(R"re(<link name="([^"]+)"/>)re");
      for (auto it = std::sregex_iterator(live.begin(), live.end(), link); it != std::sregex_iterator(); ++it)
        links.insert((*it)[1]);
      const std::string root = setup == Setup::kEyeToHand ? frames.base_frame : frames.ee_frame;
      CHECK(links.size() == joints.size() + 1);
      CHECK(links.count(root) == 1);
      for (const auto& [child, joint] : joints) {
        CHECK(links.count(child) == 1);
        CHECK(links.count(joint.parent) == 1);
      }

      const std::string tf = FormatExport(result, ExportFormat::kTfStaticYaml, frames, "result.json");
      CheckTransforms(ParseTfStatic(tf), result, frames);

      const std::string yaml = FormatExport(result, ExportFormat::kOpenCvYaml, frames, "result.json");
      cv::FileStorage fs(yaml, cv::FileStorage::READ | cv::FileStorage::MEMORY);
      const std::string cam_key = setup == Setup::kEyeToHand ? "T_base_cam" : "T_ee_cam";
      const cv::FileNode cameras = fs["cameras"];
      REQUIRE(cameras.size() == 3);
      for (int k = 0; k < 3; ++k) {
        const cv::FileNode camera = cameras[k];
        CHECK(static_cast<std::string>(camera["name"]) == result.cameras[k].name);
        CHECK(static_cast<std::string>(camera["frame_id"]) == OpticalFrame(result.cameras[k].name, frames));
        // FileStorage prints 17 significant digits: exact.
        CHECK(ReadMatrix4(camera[cam_key]).matrix() == result.cameras[k].T_cam.matrix());
        if (frames.optical_only)
          CHECK(camera[cam_key + "_link"].empty());
        else
          CheckClose(ReadMatrix4(camera[cam_key + "_link"]) * OpticalInLink(), result.cameras[k].T_cam, "link");
      }
      CHECK(ReadMatrix4(fs[setup == Setup::kEyeToHand ? "T_ee_target" : "T_base_target"]).matrix() ==
            result.T_target.matrix());
      // No camera body frame anywhere in an optical-only file, not even in comments.
      if (frames.optical_only)
        for (const std::string* text : {&launch, &urdf, &tf, &yaml}) CHECK_THAT(*text, !Contains("cam0_link"));
    }
  }
}

TEST_CASE("Frame names: options are checked, camera names must make frame names", "[io][export]") {
  ExportOptions frames;
  std::string why;
  CHECK(frames.Check(&why));
  frames.base_frame = "robot/base_link";
  CHECK(frames.Check(&why));
  frames.base_frame = "base link";
  CHECK_FALSE(frames.Check(&why));
  CHECK_THAT(why, Contains("base frame 'base link' is not a frame name"));
  frames.base_frame = "tool0";
  CHECK_FALSE(frames.Check(&why));
  CHECK_THAT(why, Contains("different names"));

  CalibrationResult result = SampleResult(Setup::kEyeToHand);
  result.cameras[1].name = "2nd camera";
  try {
    FormatExport(result, ExportFormat::kUrdf, ExportOptions{}, "r.json");
    FAIL("a camera name with a blank was exported");
  } catch (const InputError& e) {
    CHECK(e.json_path() == "/cameras/2nd camera");
    CHECK_THAT(e.what(), Contains("cannot prefix a ROS frame name"));
  }
  for (auto& camera : result.cameras) camera.calibrated = false;
  CHECK_THROWS_WITH(FormatExport(result, ExportFormat::kUrdf, ExportOptions{}, "r.json"),
                    Contains("no calibrated camera; nothing to export"));
}

TEST_CASE("The ROS names of the robot frames: base and ee as the options name them", "[io][export]") {
  ExportOptions frames;
  frames.base_frame = "world_base";
  frames.ee_frame = "flange";
  CHECK(frames.RosName("base") == "world_base");
  CHECK(frames.RosName("ee") == "flange");
  CHECK_THROWS_AS(frames.RosName("target"), std::invalid_argument);
  // The parent of the cameras is the setup's mount, the target's its holder.
  for (const Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    const std::vector<StaticTransform> transforms = StaticTransformsOf(SampleResult(setup), frames, nullptr);
    CHECK(transforms.front().parent == (setup == Setup::kEyeToHand ? "world_base" : "flange"));
    CHECK(transforms.back().parent == (setup == Setup::kEyeToHand ? "flange" : "world_base"));
    CHECK_THAT(transforms.back().what, Contains(setup == Setup::kEyeToHand ? "T_ee_target" : "T_base_target"));
  }
}

TEST_CASE("Camera frame names: checked, known cameras only, no clashes", "[io][export]") {
  ExportOptions frames;
  std::string why;
  frames.camera_frames["cam0"] = "camera/color_optical_frame";
  CHECK(frames.Check(&why));
  frames.camera_frames["cam0"] = "color optical";
  CHECK_FALSE(frames.Check(&why));
  CHECK_THAT(why, Contains("frame 'color optical' of camera 'cam0' is not a frame name"));
  frames.camera_frames = {{"", "camera_color_optical_frame"}};
  CHECK_FALSE(frames.Check(&why));
  CHECK_THAT(why, Contains("camera with no name"));

  const CalibrationResult result = SampleResult(Setup::kEyeToHand);
  frames.camera_frames = {{"cam7", "camera_color_optical_frame"}};
  try {
    FormatExport(result, ExportFormat::kTfStaticYaml, frames, "r.json");
    FAIL("a frame for an unknown camera was accepted");
  } catch (const InputError& e) {
    CHECK(e.json_path() == "/cameras");
    CHECK_THAT(e.what(), Contains("camera 'cam7', which the result does not have (cameras: cam0, cam1, cam2, cam3)"));
  }
  // An uncalibrated camera may be named: it is left out as without the name.
  frames.camera_frames = {{"cam3", "camera_color_optical_frame"}};
  CHECK_THAT(FormatExport(result, ExportFormat::kTfStaticYaml, frames, "r.json"),
             !Contains("camera_color_optical_frame"));
  // Two cameras in one frame would give the frame two parents.
  for (bool optical_only : {false, true}) {
    frames.optical_only = optical_only;
    frames.camera_frames = {{"cam0", "cam1_optical_frame"}};
    try {
      FormatExport(result, ExportFormat::kUrdf, frames, "r.json");
      FAIL("two cameras were given one frame");
    } catch (const InputError& e) {
      CHECK(e.json_path() == "/cameras/cam1");
      CHECK_THAT(e.what(), Contains("frame 'cam1_optical_frame' of camera 'cam1' clashes with another frame name"));
    }
  }
}

}  // namespace
}  // namespace handeye
