// SPDX-License-Identifier: GPL-2.0-or-later
#include <catch2/catch.hpp>

#include "handeye/core/error.h"
#include "handeye/core/evaluation.h"
#include "handeye/core/transform.h"

using namespace handeye;

TEST_CASE("Ground-truth errors are the paper's e_t and e_theta", "[evaluation]") {
  GroundTruth truth;
  truth.T_cam["cam0"] = MakeTransformFromRotationVector({0, 0, 0}, {1, 2, 3});
  truth.T_cam["cam1"] = MakeTransformFromRotationVector({0, 1, 0}, {-1, 2, 3});
  truth.T_target = Eigen::Isometry3d::Identity();
  CalibrationResult result;
  auto camera = [](const char* name, bool calibrated, const Eigen::Isometry3d& T_cam, int views) {
    CameraResult c;
    c.name = name;
    c.calibrated = calibrated;
    c.T_cam = T_cam;
    c.views = views;
    return c;
  };
  CameraResult a = camera("cam0", true, truth.T_cam["cam0"], 5);
  a.T_cam.translation() += Eigen::Vector3d(0.003, 0.004, 0);  // 5 mm
  CameraResult b = camera("cam1", true, truth.T_cam["cam1"], 5);
  b.T_cam.linear() = b.T_cam.rotation() * Eigen::AngleAxisd(0.5 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  CameraResult c = camera("cam2", false, Eigen::Isometry3d::Identity(), 0);
  result.cameras = {a, b, c};
  result.T_target = MakeTransformFromRotationVector({0, 0, 0}, {0, 0, 0.001});
  const Evaluation e = EvaluateAgainstTruth(result, truth);
  REQUIRE(e.cameras.size() == 2);
  CHECK(e.cameras[0].translation_mm == Approx(5.0));
  CHECK(e.cameras[0].rotation_deg == Approx(0.0).margin(1e-12));
  CHECK(e.cameras[1].rotation_deg == Approx(0.5));
  CHECK(e.mean_translation_mm == Approx(2.5));
  CHECK(e.mean_rotation_deg == Approx(0.25));
  CHECK(e.target_translation_mm == Approx(1.0));
  CHECK(e.missing == std::vector<std::string>{"cam2"});
  truth.setup = Setup::kEyeInHand;
  CHECK_THROWS_AS(EvaluateAgainstTruth(result, truth), InputError);
}
