// SPDX-License-Identifier: GPL-2.0-or-later
// Robot pose input (io/pose_formats.h): every spelling of T_base_ee against a
// matrix worked out by hand, the CSV pose list, and the messages for
// ambiguous or mixed specifications.
#include "handeye/io/pose_formats.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "handeye/core/error.h"
#include "handeye/io/dataset_json.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;
using nlohmann::json;

// Rotations whose entries are known exactly.
Eigen::Matrix3d Rz90() {
  Eigen::Matrix3d R;
  R << 0, -1, 0,
       1, 0, 0,
       0, 0, 1;
  return R;
}
Eigen::Matrix3d Rx90() {
  Eigen::Matrix3d R;
  R << 1, 0, 0,
       0, 0, -1,
       0, 1, 0;
  return R;
}
Eigen::Matrix3d Ry90() {
  Eigen::Matrix3d R;
  R << 0, 0, 1,
       0, 1, 0,
       -1, 0, 0;
  return R;
}
// 120° about (1, 1, 1)/√3: x → y → z → x. Also Rz(90°)·Rx(90°).
Eigen::Matrix3d Cycle() {
  Eigen::Matrix3d R;
  R << 0, 0, 1,
       1, 0, 0,
       0, 1, 0;
  return R;
}

Eigen::Isometry3d Pose(const json& value) {
  const JsonReader r(&value, "pose.json", "/T_base_ee");
  return ReadPose(r, false);
}

void RequirePoseError(const json& value, const std::string& path, const std::string& expected) {
  const JsonReader r(&value, "pose.json", "/T_base_ee");
  try {
    ReadPose(r, false);
  } catch (const InputError& e) {
    CHECK(e.file() == "pose.json");
    CHECK(e.json_path() == path);
    CHECK_THAT(e.what(), Contains(expected));
    return;
  }
  FAIL("accepted " + value.dump() + "; expected an error at " + path + ": " + expected);
}

void CheckRotation(const Eigen::Isometry3d& T, const Eigen::Matrix3d& expected, double tolerance = 1e-15) {
  INFO("got\n" << T.rotation() << "\nexpected\n" << expected);
  CHECK((T.rotation() - expected).cwiseAbs().maxCoeff() <= tolerance);
}

TEST_CASE("T_base_ee as a 4x4 array still loads", "[io][poses]") {
  const Eigen::Isometry3d T = Pose(json::parse("[[0,-1,0,0.4],[1,0,0,0.1],[0,0,1,0.9],[0,0,0,1]]"));
  CheckRotation(T, Rz90(), 0);
  CHECK(T.translation() == Eigen::Vector3d(0.4, 0.1, 0.9));
}

TEST_CASE("Quaternions in ROS (xyzw) and ABB (wxyz) order", "[io][poses]") {
  const double h = std::sqrt(0.5);
  // 90° about z: (x, y, z, w) = (0, 0, √½, √½).
  CheckRotation(Pose({{"translation_m", {0.4, 0.1, 0.9}}, {"quaternion_xyzw", {0, 0, h, h}}}), Rz90());
  // The same rotation in ABB order: (w, x, y, z) = (√½, 0, 0, √½).
  CheckRotation(Pose({{"translation_m", {0, 0, 0}}, {"quaternion_wxyz", {h, 0, 0, h}}}), Rz90());
  // An ABB RAPID orient as the controller prints it (six decimals): 90° about y.
  // [q1 q2 q3 q4] = [w x y z]. Read as xyzw it would be 180° about (x+z)/√2.
  const Eigen::Isometry3d abb =
      Pose({{"translation_mm", {1200.5, -300.25, 850}}, {"quaternion_wxyz", {0.707107, 0, 0.707107, 0}}});
  CheckRotation(abb, Ry90(), 2e-6);  // the printed digits are off by < 5e-7
  CHECK((abb.translation() - Eigen::Vector3d(1.2005, -0.30025, 0.85)).norm() < 1e-15);
  const Eigen::Isometry3d swapped =
      Pose({{"translation_m", {0, 0, 0}}, {"quaternion_xyzw", {0.707107, 0, 0.707107, 0}}});
  Eigen::Matrix3d half_turn_xz;  // 180° about (1, 0, 1)/√2
  half_turn_xz << 0, 0, 1,
                  0, -1, 0,
                  1, 0, 0;
  CheckRotation(swapped, half_turn_xz, 2e-6);
}

TEST_CASE("Rotation vectors as Universal Robots report them", "[io][poses]") {
  const Eigen::Isometry3d T = Pose({{"translation_m", {0.1, 0.2, 0.3}}, {"rotvec_rad", {0, 0, M_PI / 2}}});
  CheckRotation(T, Rz90(), 1e-15);
  const double a = 2 * M_PI / 3 / std::sqrt(3.0);  // 120° about (1, 1, 1)/√3
  CheckRotation(Pose({{"translation_m", {0, 0, 0}}, {"rotvec_rad", {a, a, a}}}), Cycle(), 1e-15);
  CHECK(T.translation() == Eigen::Vector3d(0.1, 0.2, 0.3));
}

TEST_CASE("Euler angles: KUKA A B C and ROS roll pitch yaw", "[io][poses]") {
  auto euler = [](const std::string& convention, double a, double b, double c) {
    return Pose({{"translation_m", {0, 0, 0}}, {"euler_deg", {a, b, c}}, {"euler_convention", convention}});
  };
  // Each angle alone names its axis: KUKA lists z first, ROS lists x first.
  CheckRotation(euler("kuka_abc", 90, 0, 0), Rz90());
  CheckRotation(euler("kuka_abc", 0, 90, 0), Ry90());
  CheckRotation(euler("kuka_abc", 0, 0, 90), Rx90());
  CheckRotation(euler("rpy", 90, 0, 0), Rx90());
  CheckRotation(euler("rpy", 0, 90, 0), Ry90());
  CheckRotation(euler("rpy", 0, 0, 90), Rz90());
  // Order of composition: A about z first, then C about the new x (intrinsic),
  // = Rz(90)·Rx(90); the same as rpy with roll 90 then yaw 90 about fixed axes.
  CheckRotation(euler("kuka_abc", 90, 0, 90), Cycle());
  CheckRotation(euler("rpy", 90, 0, 90), Cycle());

  // A general case against the closed form of Rz(a)·Ry(b)·Rx(c), with
  // a = 30°, b = 45°, c = 60°: sin/cos are √3/2, 1/2, √2/2.
  const double s2 = std::sqrt(2.0), s3 = std::sqrt(3.0), s6 = std::sqrt(6.0);
  Eigen::Matrix3d expected;
  expected << s6 / 4, 3 * s2 / 8 - 0.25, s6 / 8 + s3 / 4,
              s2 / 4, s6 / 8 + s3 / 4, s2 / 8 - 0.75,
              -s2 / 2, s6 / 4, s2 / 4;
  CheckRotation(euler("kuka_abc", 30, 45, 60), expected, 1e-15);
  CheckRotation(euler("rpy", 60, 45, 30), expected, 1e-15);
}

TEST_CASE("Ambiguous or mixed pose objects are rejected with a message saying what to write",
          "[io][poses]") {
  const json t = {0.1, 0.2, 0.3};
  const json q = {0, 0, 0, 1};
  RequirePoseError({{"translation_m", t}, {"quaternion_xyzw", q}, {"rotvec_rad", {0, 0, 1}}}, "/T_base_ee",
                   "give exactly one rotation; found both quaternion_xyzw and rotvec_rad");
  RequirePoseError({{"translation_m", t}, {"translation_mm", t}, {"quaternion_xyzw", q}}, "/T_base_ee",
                   "give exactly one translation");
  RequirePoseError({{"translation_m", t}}, "/T_base_ee", "missing rotation; expected one of quaternion_xyzw");
  RequirePoseError({{"quaternion_xyzw", q}}, "/T_base_ee", "missing translation");
  RequirePoseError({{"translation_m", t}, {"quaternion", q}}, "/T_base_ee/quaternion",
                   "use quaternion_xyzw [qx, qy, qz, qw] or quaternion_wxyz");
  RequirePoseError({{"translation", t}, {"quaternion_xyzw", q}}, "/T_base_ee/translation",
                   "use translation_m or translation_mm");
  RequirePoseError({{"translation_m", t}, {"rpy", {0, 0, 0}}}, "/T_base_ee/rpy", "ambiguous rotation key");
  RequirePoseError({{"translation_m", t}, {"euler_deg", {0, 0, 0}}}, "/T_base_ee/euler_convention",
                   "euler_deg needs euler_convention");
  RequirePoseError({{"translation_m", t}, {"euler_deg", {0, 0, 0}}, {"euler_convention", "zyx"}},
                   "/T_base_ee/euler_convention", "unknown Euler convention 'zyx'");
  RequirePoseError({{"translation_m", t}, {"quaternion_xyzw", q}, {"euler_convention", "rpy"}},
                   "/T_base_ee/euler_convention", "euler_convention belongs to euler_deg");
  RequirePoseError({{"translation_m", t}, {"quaternion_xyzw", {0, 0, 0, 1.01}}}, "/T_base_ee/quaternion_xyzw",
                   "a unit quaternion");
  RequirePoseError({{"translation_m", {0, 0}}, {"quaternion_xyzw", q}}, "/T_base_ee/translation_m",
                   "an array of 3 numbers");
  RequirePoseError({{"translation_m", t}, {"quaternion_xyzw", q}, {"rotvec_rads", {0, 0, 1}}},
                   "/T_base_ee/rotvec_rads", "did you mean 'rotvec_rad'?");
  RequirePoseError("0001", "/T_base_ee", "a 4x4 array of numbers (row-major) or a pose object");

  // --reorthonormalise normalises instead.
  const json scaled = {{"translation_m", t}, {"quaternion_xyzw", {0, 0, 2 * std::sqrt(0.5), 2 * std::sqrt(0.5)}}};
  const JsonReader r(&scaled, "pose.json", "/T_base_ee");
  CheckRotation(ReadPose(r, true), Rz90());
}

TEST_CASE("The dataset loader reads pose objects and names the pose in errors", "[io][poses]") {
  const std::string dir = test::TempDir("pose_formats_dataset");
  json doc = json::parse(R"({
    "format": "handeye-dataset/1", "setup": "eye_to_hand",
    "target": {"type": "checkerboard", "inner_corners": [4, 3], "square_size_m": 0.05},
    "cameras": [{"name": "cam0", "image_size": [640, 480],
                 "intrinsics": {"fx": 500, "fy": 500, "cx": 319.5, "cy": 239.5},
                 "distortion": {"model": "none"}}],
    "poses": [
      {"id": "ur", "T_base_ee": {"translation_m": [0.5, 0, 0.3], "rotvec_rad": [0, 0, 1.5707963267948966]},
       "images": {}},
      {"id": "kuka", "T_base_ee": {"translation_mm": [500, 0, 300], "euler_deg": [90, 0, 90],
                                   "euler_convention": "kuka_abc"},
       "images": {}}
    ]
  })");
  test::WriteText(dir + "/dataset.json", doc.dump());
  const Dataset d = LoadDataset(dir + "/dataset.json");
  REQUIRE(d.poses.size() == 2);
  CheckRotation(d.poses[0].T_base_ee, Rz90(), 1e-15);
  CheckRotation(d.poses[1].T_base_ee, Cycle(), 1e-15);
  CHECK((d.poses[1].T_base_ee.translation() - Eigen::Vector3d(0.5, 0, 0.3)).norm() < 1e-15);

  doc["poses"][1]["T_base_ee"]["quaternion_wxyz"] = {1, 0, 0, 0};
  test::WriteText(dir + "/bad.json", doc.dump());
  try {
    LoadDataset(dir + "/bad.json");
    FAIL("a pose with two rotations was accepted");
  } catch (const InputError& e) {
    CHECK(e.json_path() == "/poses/1/T_base_ee");
    CHECK_THAT(e.what(), Contains(dir + "/bad.json: at /poses/1/T_base_ee: give exactly one rotation"));
  }
}

TEST_CASE("CSV pose lists", "[io][poses][csv]") {
  const std::string dir = test::TempDir("pose_csv");
  const double h = std::sqrt(0.5);
  char row[200];
  std::snprintf(row, sizeof(row), "0002, 1200.5, -300.25, 850, 0, 0, %.17g, %.17g\r\n", h, h);
  test::WriteText(dir + "/poses.csv",
                  "# exported from the robot\n"
                  "id,x,y,z,qx,qy,qz,qw\n"
                  "\"0001\",400,100,900,0,0,0,1\n" +
                      std::string(row) + "\n");
  const std::vector<PoseRow> mm = ReadPoseCsv(dir + "/poses.csv", LengthUnit::kMillimetre, false);
  REQUIRE(mm.size() == 2);
  CHECK(mm[0].id == "0001");  // quoted: the zeros stay
  CHECK(mm[0].line == 3);
  CHECK(mm[0].T_base_ee.rotation() == Eigen::Matrix3d::Identity());
  CHECK((mm[0].T_base_ee.translation() - Eigen::Vector3d(0.4, 0.1, 0.9)).norm() < 1e-15);
  CHECK(mm[1].id == "0002");
  CheckRotation(mm[1].T_base_ee, Rz90());
  CHECK((mm[1].T_base_ee.translation() - Eigen::Vector3d(1.2005, -0.30025, 0.85)).norm() < 1e-15);
  const std::vector<PoseRow> m = ReadPoseCsv(dir + "/poses.csv", LengthUnit::kMetre, false);
  CHECK(m[1].T_base_ee.translation() == Eigen::Vector3d(1200.5, -300.25, 850));

  auto require_csv_error = [&](const std::string& text, const std::string& expected) {
    test::WriteText(dir + "/bad.csv", text);
    try {
      ReadPoseCsv(dir + "/bad.csv", LengthUnit::kMetre, false);
    } catch (const InputError& e) {
      CHECK(e.file() == dir + "/bad.csv");
      CHECK_THAT(e.what(), Contains(expected));
      return;
    }
    FAIL("accepted:\n" + text);
  };
  require_csv_error("id,x,y,z,qw,qx,qy,qz\n1,0,0,0,1,0,0,0\n",
                    "line 1: expected one of the headers 'id,x,y,z,qx,qy,qz,qw' (quaternion x y z w)");
  require_csv_error("id,x,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0\n", "line 2: expected 8 comma-separated fields");
  require_csv_error("id,x,y,z,qx,qy,qz,qw\n1,0,0,zero,0,0,0,1\n", "line 2: column z: expected a finite number");
  require_csv_error("id,x,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0,1\n\n1,0,0,0,0,0,0,1\n",
                    "line 4: duplicate pose id '1' (also on line 2)");
  require_csv_error("id,x,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0,0.9\n", "line 2: columns qx,qy,qz,qw: expected a unit");
  require_csv_error("id,x,y,z,qx,qy,qz,qw\n,0,0,0,0,0,0,1\n", "line 2: column id: expected a pose id");
  require_csv_error("id,x,y,z,qx,qy,qz,qw\n", "no poses");
  require_csv_error("", "empty file; expected a header row and rows: 'id,x,y,z,qx,qy,qz,qw'");
  CHECK_THROWS_WITH(ReadPoseCsv(dir + "/missing.csv", LengthUnit::kMetre, false),
                    Contains("missing.csv: file does not exist"));
}

}  // namespace
}  // namespace handeye
