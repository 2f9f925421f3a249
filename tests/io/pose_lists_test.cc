// SPDX-License-Identifier: GPL-2.0-or-later
// Robot pose lists as controllers print them (io/pose_formats.h): CSV with a
// rotation vector (Universal Robots), KUKA A B C or roll pitch yaw, YAML
// lists of ROS geometry_msgs/Pose, and the reach check that catches a unit
// mistake.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "dataset_json_fixtures.h"
#include "handeye/core/error.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/pose_formats.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;

// 120° about (1, 1, 1)/√3: x → y → z → x; Rz(90°)·Rx(90°).
Eigen::Matrix3d AxisCycle() {
  Eigen::Matrix3d R;
  R << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  return R;
}

void CheckPose(const PoseRow& row, const std::string& id, const Eigen::Vector3d& t,
               const Eigen::Matrix3d& R) {
  INFO(row.id);
  CHECK(row.id == id);
  CHECK((row.T_base_ee.translation() - t).norm() < 1e-12);
  CHECK((row.T_base_ee.rotation() - R).cwiseAbs().maxCoeff() < 1e-12);
}

std::string PoseListErrorOf(const std::string& path, const PoseListOptions& options) {
  try {
    ReadPoseList(path, options);
  } catch (const InputError& e) {
    CHECK(e.file() == path);
    return e.what();
  }
  return "";
}

TEST_CASE("CSV pose lists with a rotation vector, KUKA A B C or roll pitch yaw",
          "[io][poses][csv]") {
  const std::string dir = test::TempDir("pose_lists_csv");
  const double angle = 2 * M_PI / 3, axis = angle / std::sqrt(3.0);
  char rotvec[200];
  std::snprintf(
      rotvec, sizeof rotvec,
      "ID, X, Y, Z, RX, RY, RZ\n0001,400,-100,900,0,0,0\n0002,500,0,800,%.17g,%.17g,%.17g\n", axis,
      axis, axis);
  test::WriteText(dir + "/ur.csv", rotvec);
  // AxisCycle() is Rz(90)·Ry(0)·Rx(90): KUKA lists the z angle first, ROS last.
  test::WriteText(dir + "/kuka.csv",
                  "id,x,y,z,a,b,c\n0001,400,-100,900,0,0,0\n0002,500,0,800,90,0,90\n");
  test::WriteText(dir + "/ros.csv",
                  "id,x,y,z,roll,pitch,yaw\n0001,400,-100,900,0,0,0\n0002,500,0,800,90,0,90\n");
  PoseListOptions mm;
  mm.unit = LengthUnit::kMillimetre;
  for (const char* name : {"ur.csv", "kuka.csv", "ros.csv"}) {
    INFO(name);
    const std::vector<PoseRow> rows = ReadPoseList(dir + "/" + name, mm);
    REQUIRE(rows.size() == 2);
    CheckPose(rows[0], "0001", {0.4, -0.1, 0.9}, Eigen::Matrix3d::Identity());
    CheckPose(rows[1], "0002", {0.5, 0, 0.8}, AxisCycle());
    CHECK(rows[1].line == 3);
  }
  // Another header, named by --rotation: the columns count, not their names.
  test::WriteText(dir + "/own.csv", "pose,tx,ty,tz,A_deg,B_deg,C_deg\n7,0.5,0,0.8,90,0,90\n");
  PoseListOptions kuka;
  kuka.rotation = CsvRotation::kKukaAbc;
  CheckPose(ReadPoseList(dir + "/own.csv", kuka).front(), "7", {0.5, 0, 0.8}, AxisCycle());
  CHECK_THAT(
      PoseListErrorOf(dir + "/own.csv", {}),
      Contains("line 1: expected one of the headers 'id,x,y,z,qx,qy,qz,qw' (quaternion x y z w), "
               "'id,x,y,z,rx,ry,rz' (rotation vector in radians), 'id,x,y,z,a,b,c' (KUKA A B C in "
               "degrees), "
               "'id,x,y,z,roll,pitch,yaw' (roll pitch yaw in degrees); x, y, z in metres "
               "(--rotation names "
               "the form for other headers), got 'pose,tx,ty,tz,A_deg,B_deg,C_deg'"));
  PoseListOptions quaternion;
  quaternion.rotation = CsvRotation::kQuaternion;
  CHECK_THAT(PoseListErrorOf(dir + "/own.csv", quaternion),
             Contains("line 1: expected a header of 8 columns for --rotation quaternion "
                      "(id,x,y,z,qx,qy,qz,qw), got 7"));
  test::WriteText(dir + "/short.csv", "id,x,y,z,rx,ry,rz\n1,0.5,0,0.8,0,0\n");
  CHECK_THAT(PoseListErrorOf(dir + "/short.csv", {}),
             Contains("line 2: expected 7 comma-separated fields (id,x,y,z,rx,ry,rz), got 6"));
  test::WriteText(dir + "/nan.csv", "id,x,y,z,a,b,c\n1,0.5,0,0.8,0,nan,0\n");
  CHECK_THAT(PoseListErrorOf(dir + "/nan.csv", {}),
             Contains("line 2: column b: expected a finite number, got 'nan'"));
  for (const auto& [name, rotation] :
       {std::pair<const char*, CsvRotation>{"quaternion", CsvRotation::kQuaternion},
        {"rotvec", CsvRotation::kRotationVector},
        {"kuka_abc", CsvRotation::kKukaAbc},
        {"rpy", CsvRotation::kRpy}}) {
    CHECK(ParseCsvRotation(name) == rotation);
    CHECK(CsvRotationName(rotation) == std::string(name));
  }
  CHECK(!ParseCsvRotation("euler"));
}

TEST_CASE("YAML lists of ROS geometry_msgs/Pose, PoseArray and PoseStamped", "[io][poses][yaml]") {
  const std::string dir = test::TempDir("pose_lists_yaml");
  const double h = std::sqrt(0.5);
  Eigen::Matrix3d Rz90;
  Rz90 << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  char text[600];
  std::snprintf(text, sizeof text,
                "- id: \"0001\"\n  position: {x: 0.4, y: -0.1, z: 0.9}\n  orientation: {x: 0, y: "
                "0, z: 0, w: 1}\n"
                "- id: 12\n  position:\n    x: 0.5\n    y: 0\n    z: 0.8\n  orientation:\n    x: "
                "0\n    y: 0\n"
                "    z: %.17g\n    w: %.17g\n",
                h, h);
  test::WriteText(dir + "/list.yaml", text);
  std::vector<PoseRow> rows = ReadPoseList(dir + "/list.yaml", {});
  REQUIRE(rows.size() == 2);
  CheckPose(rows[0], "0001", {0.4, -0.1, 0.9}, Eigen::Matrix3d::Identity());
  CheckPose(rows[1], "12", {0.5, 0, 0.8}, Rz90);
  CHECK(rows[1].line == 0);

  // `rostopic echo` of a PoseArray: no ids, numbered from 0001.
  test::WriteText(
      dir + "/array.yml",
      "header:\n  seq: 1\n  frame_id: base_link\nposes:\n"
      "  -\n    position: {x: 400, y: -100, z: 900}\n    orientation: {x: 0, y: 0, z: 0, w: 1}\n"
      "  -\n    position: {x: 500, y: 0, z: 800}\n    orientation: {x: 0.5, y: 0.5, z: 0.5, w: "
      "0.5}\n");
  PoseListOptions mm;
  mm.unit = LengthUnit::kMillimetre;
  rows = ReadPoseList(dir + "/array.yml", mm);
  REQUIRE(rows.size() == 2);
  CheckPose(rows[0], "0001", {0.4, -0.1, 0.9}, Eigen::Matrix3d::Identity());
  CheckPose(rows[1], "0002", {0.5, 0, 0.8}, AxisCycle());

  test::WriteText(dir + "/stamped.yaml",
                  "- header: {frame_id: base_link}\n  pose:\n    position: {x: 0.5, y: 0, z: 0.8}\n"
                  "    orientation: {x: 0.5, y: 0.5, z: 0.5, w: 0.5}\n");
  CheckPose(ReadPoseList(dir + "/stamped.yaml", {}).front(), "0001", {0.5, 0, 0.8}, AxisCycle());

  auto require_error = [&](const std::string& yaml, const std::string& path,
                           const std::string& expected) {
    test::WriteText(dir + "/bad.yaml", yaml);
    test::RequireInputErrorAt(dir + "/bad.yaml", path, expected,
                              [&] { ReadPoseList(dir + "/bad.yaml", {}); });
  };
  const std::string good =
      "  position: {x: 0.5, y: 0, z: 0.8}\n  orientation: {x: 0, y: 0, z: 0, w: 1}\n";
  require_error(
      "- id: a\n  position: {x: 0.5, y: 0, z: 0.8}\n  orientation: {x: 0, y: 0, z: 0, w: 0.9}\n",
      "/0/orientation", "expected a unit quaternion");
  require_error("- id: a\n" + good + "- id: a\n" + good, "/1",
                "duplicate pose id 'a' (also at /0)");
  require_error("- id: a\n  position: {x: 0.5, y: 0}\n  orientation: {x: 0, y: 0, z: 0, w: 1}\n",
                "/0/position/z", "missing key");
  require_error(
      "- id: a\n  position: {x: 0.5, y: 0, z: 0.8}\n  quaternion: {x: 0, y: 0, z: 0, w: 1}\n",
      "/0/quaternion", "quaternion");
  require_error("poses: []\n", "/poses", "no poses");
  test::WriteText(dir + "/bad.yaml", "a: 1\n");
  CHECK_THAT(PoseListErrorOf(dir + "/bad.yaml", {}),
             Contains("bad.yaml: expected a list of geometry_msgs/Pose"));
}

// An error about the whole file: "<file>: <what>".
template <typename Load>
void RequirePoseListError(const std::string& file, const std::string& expected, Load&& load) {
  try {
    load();
  } catch (const InputError& e) {
    CHECK(e.file() == file);
    CHECK(e.json_path().empty());
    CHECK_THAT(e.what(), Contains(file + ": " + expected));
    return;
  }
  FAIL(file + " was accepted; expected: " + expected);
}

TEST_CASE("A pose list whose reach says the unit is wrong is refused, naming the unit option",
          "[io][poses]") {
  const std::string dir = test::TempDir("pose_lists_reach");
  test::WriteText(dir + "/poses.csv",
                  "id,x,y,z,qx,qy,qz,qw\n1,400,100,900,0,0,0,1\n2,450,-20,880,0,0,0,1\n");
  const std::vector<PoseRow> metres = ReadPoseList(dir + "/poses.csv", {});
  RequirePoseListError(
      dir + "/poses.csv",
      "pose '1' (line 2) is 989.9 m from the robot base with x, y, z read as metres, "
      "farther than a robot reaches (10 m); if they are millimetres, use --translation-unit mm",
      [&] {
        RequirePlausibleReach(metres, dir + "/poses.csv", LengthUnit::kMetre, "--translation-unit");
      });
  PoseListOptions mm;
  mm.unit = LengthUnit::kMillimetre;
  RequirePlausibleReach(ReadPoseList(dir + "/poses.csv", mm), dir + "/poses.csv", mm.unit,
                        "--translation-unit");
  // Metres read as millimetres: 0.99 m becomes 0.99 mm.
  test::WriteText(dir + "/metres.csv",
                  "id,x,y,z,qx,qy,qz,qw\n1,0.4,0.1,0.9,0,0,0,1\n2,0.45,-0.02,0.88,0,0,0,1\n");
  RequirePoseListError(
      dir + "/metres.csv",
      "every pose is within 10 mm of the robot base with x, y, z read as millimetres (the "
      "farthest, pose '1' (line 2), 0.9899 mm); if they are metres, use --translation-unit m",
      [&] {
        RequirePlausibleReach(ReadPoseList(dir + "/metres.csv", mm), dir + "/metres.csv", mm.unit,
                              "--translation-unit");
      });
  CHECK(!ImplausibleReach({Eigen::Vector3d(9.9, 0, 0), Eigen::Vector3d(0, 0, 0)}));
  CHECK(ImplausibleReach({Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(0, 10.1, 0)}) ==
        std::size_t{1});
  CHECK(!ImplausibleReach({Eigen::Vector3d(0, 0, 0.001)}));  // one pose says little
}

TEST_CASE(
    "A dataset whose robot poses are a kilometre away names the unit instead of failing in the "
    "solver",
    "[io][dataset][poses]") {
  nlohmann::json j = test::ValidDatasetJson();
  j["poses"][1]["T_base_ee"] = {{0, -1, 0, 400}, {1, 0, 0, 100}, {0, 0, 1, 900}, {0, 0, 0, 1}};
  test::RequireLoadError(
      j, "/poses/1/T_base_ee",
      "expected a translation in metres; this one puts the flange 989.9 m from the robot base, "
      "farther than a robot reaches (10 m): millimetres written as metres?");
  j = test::ValidDatasetJson();
  j["poses"][1]["T_base_ee"] = {{"translation_mm", {400, 100, 900}}, {"rotvec_rad", {0, 0, 0}}};
  LoadDataset(test::WriteJson(test::TempDir("dataset_reach") + "/d.json", j));
}

}  // namespace
}  // namespace handeye
