// SPDX-License-Identifier: GPL-2.0-or-later
// handeye-cell/1 round trip and its bad-input messages.
#include <catch2/catch.hpp>
#include <string>

#include "handeye/core/checkerboard.h"
#include "handeye/core/error.h"
#include "handeye/io/plan_json.h"
#include "support/test_support.h"

using namespace handeye;

namespace {

PlanCell SmallCell() {
  PlanCell cell;
  cell.target = std::make_shared<const CheckerboardTarget>(7, 4, 0.04);
  PlanCamera camera;
  camera.camera = *Camera::Make("left", 1280, 720, 900, 901, 640, 360, {}, nullptr);
  camera.T_mount_cam.translation() = Eigen::Vector3d(2.0, 0.1, 2.2);
  camera.position_sigma_m = 0.02;
  camera.rotation_sigma_rad = 0.03;
  camera.refine_intrinsics = true;
  cell.cameras.push_back(camera);
  cell.T_holder_target.translation() = Eigen::Vector3d(0, 0, 0.1);
  cell.region.box = Eigen::AlignedBox3d(Eigen::Vector3d(-0.5, -0.5, 0.6), Eigen::Vector3d(0.5, 0.5, 1.4));
  cell.region.taught.push_back(Eigen::Isometry3d::Identity());
  cell.region.tilt_axis = Eigen::Vector3d(0, 0, -1);
  cell.region.max_tilt_rad = 2.0;
  cell.constraints.margin_px = 30;
  return cell;
}

std::string PlanCellErrorOf(const std::string& path) {
  try {
    LoadPlanCell(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("A cell file reads back as it was written", "[plan][io]") {
  const std::string path = test::TempDir("cell_round_trip") + "/cell.json";
  PlanCell cell = SmallCell();
  cell.intrinsics_sigma = {0.5, 2.0};
  cell.cameras[0].pixel_sigma_px = 0.7;  // a camera that detects unlike the others
  SavePlanCell(cell, path);
  const PlanCell back = LoadPlanCell(path);
  CHECK(back.intrinsics_sigma.focal_percent == 0.5);
  CHECK(back.intrinsics_sigma.principal_point_px == 2.0);
  REQUIRE(back.cameras.size() == 1);
  CHECK(back.cameras[0].camera.name == "left");
  CHECK(back.cameras[0].camera.fy() == 901);
  CHECK(back.cameras[0].refine_intrinsics);
  CHECK(back.cameras[0].T_mount_cam.isApprox(cell.cameras[0].T_mount_cam, 1e-12));
  CHECK(back.cameras[0].rotation_sigma_rad == Approx(0.03));
  CHECK(back.cameras[0].pixel_sigma_px == 0.7);
  CHECK(back.T_holder_target.isApprox(cell.T_holder_target, 1e-12));
  CHECK(back.region.box->isApprox(*cell.region.box));
  CHECK(back.region.taught.size() == 1);
  CHECK(back.region.max_tilt_rad == Approx(2.0));
  CHECK(back.region.tilt_axis.isApprox(cell.region.tilt_axis));
  CHECK(back.constraints.margin_px == 30);
  CHECK(back.target->Points().size() == 28);
  CHECK_FALSE(back.cameras[0].intrinsics_unknown);
}

TEST_CASE("A cell camera of unknown intrinsics reads back as its field of view", "[plan][io]") {
  const std::string path = test::TempDir("cell_unknown") + "/cell.json";
  PlanCell cell = SmallCell();
  cell.cameras[0].camera = *Camera::Make("left", 1280, 720, 900, 900, 639.5, 359.5, {}, nullptr);
  cell.cameras[0].intrinsics_unknown = true;
  SavePlanCell(cell, path);
  CHECK(test::ReadText(path).find("horizontal_fov_deg") != std::string::npos);
  const PlanCell back = LoadPlanCell(path);
  REQUIRE(back.cameras.size() == 1);
  CHECK(back.cameras[0].intrinsics_unknown);
  CHECK(back.cameras[0].refine_intrinsics);
  CHECK(back.cameras[0].camera.fx() == Approx(900));
  CHECK(back.cameras[0].camera.cx() == Approx(639.5));
}

TEST_CASE("A cell file's mistakes are named with their path", "[plan][io]") {
  const std::string dir = test::TempDir("cell_bad");
  SavePlanCell(SmallCell(), dir + "/good.json");
  const std::string good = test::ReadText(dir + "/good.json");
  auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
    test::WriteText(dir + "/bad.json", text);
    return PlanCellErrorOf(dir + "/bad.json");
  };
  CHECK_THAT(with("\"intrinsics\"", "\"intrinsix\""), Catch::Contains("/cameras/0"));
  CHECK_THAT(with("\"min\": [-0.5", "\"min\": [0.7"),
             Catch::Contains("/region/box_m") && Catch::Contains("min below max"));
  CHECK_THAT(with("\"max_deg\"", "\"max_dag\""), Catch::Contains("/region/tilt"));
  CHECK_THAT(with("\"handeye-cell/1\"", "\"handeye-cell/2\""), Catch::Contains("/format"));
  CHECK_THAT(with("\"focal_percent\"", "\"focal\""), Catch::Contains("/noise/intrinsics_sigma"));
  CHECK_THAT(with("\"principal_point_px\": 3", "\"principal_point_px\": -3"),
             Catch::Contains("intrinsics_sigma"));
}
