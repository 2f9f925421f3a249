// SPDX-License-Identifier: GPL-2.0-or-later
// The robot model the joint solve takes by default (core/src/calibrate_joint.cc,
// ModelChosenRounds): where the views show the robot's error only a little,
// held-out poses choose between the exact robot and the modelled one.

#include <catch2/catch.hpp>
#include <cmath>
#include <utility>

#include "handeye/core/calibration.h"
#include "handeye/core/evaluation.h"
#include "support/projected_scene.h"

using namespace handeye;

namespace {

// A medium cell of 4 cameras and 30 poses, corners projected with 0.1 px of
// noise: at a robot error of 0.1 mm / 0.01° its chain residuals are only a
// little above PnP's.
SyntheticScene Scene(std::uint64_t seed, double robot_mm, double robot_deg) {
  SceneOptions options;
  options.cell = "medium";
  options.num_cameras = 4;
  options.num_poses = 30;
  options.seed = seed;
  options.pose_noise_mm = robot_mm;
  options.pose_noise_deg = robot_deg;
  return test::ProjectedScene(options, 0.1, 4, seed * 31 + 7);
}

double MeanErrorMm(const Dataset& dataset, const CalibrationOptions& options,
                   const GroundTruth& truth, CalibrationResult* result = nullptr) {
  CalibrationResult solved = Calibrate(dataset, options);
  const double mm = EvaluateAgainstTruth(solved, truth).mean_translation_mm;
  if (result) *result = std::move(solved);
  return mm;
}

CalibrationOptions RobotSigma(double mm, double deg) {
  CalibrationOptions options;
  options.robot_sigma_mm = mm;
  options.robot_sigma_deg = deg;
  return options;
}

}  // namespace

TEST_CASE("a robot error the views show only a little is modelled where held-out poses say so",
          "[robot_model]") {
  for (const std::uint64_t seed : {1, 2}) {
    INFO("seed " << seed);
    const SyntheticScene scene = Scene(seed, 0.1, 0.01);
    CalibrationResult result;
    const double by_default =
        MeanErrorMm(scene.dataset, CalibrationOptions{}, scene.truth, &result);
    // The simulator's rotation error is 0.01° about a random axis: σ per axis 0.01/√3.
    const double given =
        MeanErrorMm(scene.dataset, RobotSigma(0.1, 0.01 / std::sqrt(3.0)), scene.truth);
    const double exact = MeanErrorMm(scene.dataset, RobotSigma(0, 0), scene.truth);
    INFO("default " << by_default << " mm, given the robot's sigma " << given << " mm, exact robot "
                    << exact << " mm");
    REQUIRE(result.solver.model);
    CHECK(result.solver.model->chosen != "exact robot");
    // Measured: 0.27-0.31 mm by default, 0.48-0.62 with the exact robot (the
    // default before held-out poses chose here).
    CHECK(by_default < 1.15 * given);
    CHECK(by_default < 0.7 * exact);
  }
}

TEST_CASE("an exact robot whose views show no error is solved as exact by default",
          "[robot_model]") {
  for (const std::uint64_t seed : {1, 2, 3}) {
    INFO("seed " << seed);
    const SyntheticScene scene = Scene(seed, 0.0, 0.0);
    CalibrationResult result;
    const double by_default =
        MeanErrorMm(scene.dataset, CalibrationOptions{}, scene.truth, &result);
    const double exact = MeanErrorMm(scene.dataset, RobotSigma(0, 0), scene.truth);
    CHECK(result.solver.robot_sigma_mm == 0.0);
    // Nor does it pay the held-out choice: the target lies across the viewing
    // rays where PnP's noise puts it (a 32-camera cell: 5.4 s, with the
    // choice 23 s).
    CHECK_FALSE(result.solver.model);
    CHECK(by_default == Approx(exact).epsilon(1e-6));
  }
}
