// SPDX-License-Identifier: GPL-2.0-or-later
// The frame-explicit readings of a result: each setup answers in its own
// frames, refuses the other's with what to read instead, and places a camera
// in the base frame at any robot pose.
#include <catch2/catch.hpp>
#include <memory>
#include <random>
#include <stdexcept>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/transform.h"
#include "handeye/sim/synthetic.h"
#include "support/projected_scene.h"

using namespace handeye;

namespace {

SyntheticScene ResultScene(Setup setup) {
  return test::ProjectedScene("small", 2, 12, 11, 0.05, setup);
}

double DistanceMm(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return 1000.0 * (a.translation() - b.translation()).norm();
}

}  // namespace

TEST_CASE(
    "An eye-to-hand result reads as T_base_cam and T_ee_target, and refuses the flange frames") {
  const SyntheticScene scene = ResultScene(Setup::kEyeToHand);
  const CalibrationResult result = Calibrate(scene.dataset, CalibrationOptions());
  const std::string cam = scene.dataset.cameras[0].name;
  CHECK(DistanceMm(result.T_base_cam(cam), scene.truth.T_cam.at(cam)) < 0.5);
  CHECK(DistanceMm(result.T_ee_target(), scene.truth.T_target) < 0.5);
  // The robot does not move a camera fixed in the cell.
  const Eigen::Isometry3d T_base_ee = scene.dataset.poses[3].T_base_ee;
  CHECK(result.T_base_cam_at(cam, T_base_ee).isApprox(result.T_base_cam(cam)));
  CHECK_THROWS_WITH(result.T_ee_cam(cam), Catch::Contains("this result is eye_to_hand") &&
                                              Catch::Contains("read T_base_cam"));
  CHECK_THROWS_AS(result.T_base_target(), std::logic_error);
  CHECK_THROWS_WITH(result.T_base_cam("no_such_camera"),
                    Catch::Contains("no camera 'no_such_camera'"));
  CalibrationResult uncalibrated = result;
  uncalibrated.cameras[1].calibrated = false;
  CHECK_THROWS_AS(uncalibrated.T_base_cam(scene.dataset.cameras[1].name), std::out_of_range);
}

TEST_CASE(
    "An eye-in-hand result reads as T_ee_cam and T_base_target, and places the camera at a robot "
    "pose") {
  const SyntheticScene scene = ResultScene(Setup::kEyeInHand);
  const CalibrationResult result = Calibrate(scene.dataset, CalibrationOptions());
  const std::string cam = scene.dataset.cameras[1].name;
  CHECK(DistanceMm(result.T_ee_cam(cam), scene.truth.T_cam.at(cam)) < 0.5);
  CHECK(DistanceMm(result.T_base_target(), scene.truth.T_target) < 0.5);
  const Eigen::Isometry3d T_base_ee = scene.dataset.poses[5].T_base_ee;
  CHECK(DistanceMm(result.T_base_cam_at(cam, T_base_ee), T_base_ee * scene.truth.T_cam.at(cam)) <
        0.5);
  CHECK_THROWS_WITH(result.T_base_cam(cam), Catch::Contains("this result is eye_in_hand") &&
                                                Catch::Contains("T_base_cam_at"));
  CHECK_THROWS_WITH(result.T_ee_target(), Catch::Contains("read T_base_target"));
}
