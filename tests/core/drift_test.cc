// SPDX-License-Identifier: GPL-2.0-or-later
// handeye check: a camera knocked after calibration is found, the others are
// cleared; held cameras anchor the recalibration of the moved one.
#include "handeye/core/drift.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>

#include "handeye/core/checkerboard.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "handeye/sim/synthetic.h"

using namespace handeye;

namespace {

SyntheticScene Capture(int poses, std::uint64_t pose_seed, const std::string& bumped = "",
                       double robot_mm = 0.1) {
  SceneOptions options;
  options.cell = "medium";
  options.num_cameras = 4;
  options.num_poses = poses;
  options.seed = 21;
  options.pose_seed = pose_seed;
  options.pose_noise_mm = robot_mm;
  options.pose_noise_deg = robot_mm / 10;
  options.bumped_camera = bumped;
  options.bump_mm = 5.0;
  options.bump_deg = 0.2;
  SyntheticScene scene = MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
  std::mt19937_64 rng(pose_seed * 7 + 1);
  AddProjectedObservations(&scene, 0.1, &rng);
  return scene;
}

}  // namespace

TEST_CASE("A later capture of the same cell keeps its cameras and moves the robot", "[drift]") {
  const SyntheticScene first = Capture(20, 0), later = Capture(8, 99), bumped = Capture(8, 99, "cam1");
  for (const auto& [name, T] : first.truth.T_cam) CHECK(later.truth.T_cam.at(name).isApprox(T));
  CHECK_FALSE(first.truth.poses[0].T_base_ee_true.isApprox(later.truth.poses[0].T_base_ee_true));
  const Eigen::Isometry3d& a = first.truth.T_cam.at("cam1");
  const Eigen::Isometry3d& b = bumped.truth.T_cam.at("cam1");
  CHECK(1000.0 * (a.translation() - b.translation()).norm() == Approx(5.0));
  CHECK(RotationDistance(a.rotation(), b.rotation()) * 180.0 / M_PI == Approx(0.2));
}

TEST_CASE("check names the camera that was knocked and clears the others", "[drift]") {
  const CalibrationResult calibration = Calibrate(Capture(20, 0).dataset, CalibrationOptions{});
  DriftOptions options;
  const DriftResult quiet = CheckDrift(Capture(8, 99).dataset, calibration, options);
  CHECK_FALSE(quiet.AnyMoved());
  for (const CameraDrift& c : quiet.cameras) {
    INFO(c.name << " " << c.moved_mm << " ± " << c.sigma_mm << " mm " << c.moved_deg << " ± " << c.sigma_deg << " deg, " << c.views << " views");
    // Within the tolerances: ok. Beyond one but within the check's noise (3
    // views tell a camera to ≈ 0.7 mm, against a 1 mm tolerance): the check
    // cannot tell, and says so rather than clearing the camera; only beyond
    // 2σ (a little more where the robot's σ was estimated) does it say the
    // camera seems to have moved.
    const bool within = c.moved_mm <= options.tolerance_mm && c.moved_deg <= options.tolerance_deg;
    CHECK(c.verdict == (within ? "ok" : "not_assessed"));
    const bool hint = c.moved_mm > 2.0 * c.sigma_mm || c.moved_deg > 2.0 * c.sigma_deg;
    const bool seems = c.reason.find("seems") != std::string::npos;
    if (!within)
      CHECK_THAT(c.reason, Catch::Matchers::Contains(seems ? "σ of the noise of the check ("
                                                           : "too coarse to tell a move of 1 mm"));
    if (seems) CHECK(hint);
    // 3 views of 8 noisy poses tell a camera's pose to ≈ 0.5 mm, the
    // calibration to ≈ 0.7: an unmoved camera is within 3σ of both.
    CHECK(c.moved_mm < 3.0 * c.sigma_mm);
    CHECK(c.sigma_mm > 0.0);
  }
  const DriftResult knocked = CheckDrift(Capture(8, 99, "cam1").dataset, calibration, options);
  CHECK(knocked.AnyMoved());
  for (const CameraDrift& c : knocked.cameras) {
    INFO(c.name << " " << c.moved_mm << " mm " << c.moved_deg << " deg");
    if (c.name == "cam1") {
      CHECK(c.verdict == "moved");
      CHECK(c.moved_mm > 4.0);
      CHECK(c.moved_mm < 6.0);
      CHECK(c.moved_deg == Approx(0.2).margin(0.03));
    } else {
      CHECK(c.verdict != "moved");
      CHECK(c.moved_mm < 3.0 * c.sigma_mm);
    }
  }

  // Recalibrating with the three unmoved cameras held finds cam1's new pose.
  CalibrationOptions keep;
  for (const CameraResult& c : calibration.cameras)
    if (c.name != "cam1") keep.fixed_cameras[c.name] = c.T_cam;
  const SyntheticScene bumped = Capture(8, 99, "cam1");
  const CalibrationResult again = Calibrate(bumped.dataset, keep);
  for (const CameraResult& c : again.cameras) {
    const double e_mm = 1000.0 * (c.T_cam.translation() - bumped.truth.T_cam.at(c.name).translation()).norm();
    INFO(c.name << " " << e_mm << " mm from the truth");
    CHECK(e_mm < 1.0);
    if (c.name != "cam1") CHECK(c.T_cam.isApprox(keep.fixed_cameras.at(c.name)));
  }
}

TEST_CASE("check rejects a result of another cell and a camera without new views", "[drift]") {
  const CalibrationResult calibration = Calibrate(Capture(20, 0).dataset, CalibrationOptions{});
  Dataset later = Capture(8, 99).dataset;
  std::vector<Observation> without_cam2;
  for (const Observation& obs : later.observations)
    if (obs.camera != "cam2") without_cam2.push_back(obs);
  later.observations = without_cam2;
  const DriftResult drift = CheckDrift(later, calibration, DriftOptions{});
  CHECK(drift.cameras[2].verdict == "not_assessed");
  CHECK_THAT(drift.cameras[2].reason, Catch::Contains("not seen"));
  CHECK(drift.AnyNotAssessed());
  CHECK_FALSE(drift.cameras[2].estimated);
  CHECK(drift.cameras[0].estimated);
  CHECK_FALSE(drift.AnyMoved());
  later.setup = Setup::kEyeInHand;
  CHECK_THROWS_AS(CheckDrift(later, calibration, DriftOptions{}), InputError);
}

TEST_CASE("check counts the new poses' robot error in its noise where the calibration modelled it",
          "[drift]") {
  // Robot poses 0.1 mm / 0.01° off: each new pose moves the camera found
  // through it rigidly (0.01° at 2-3 m is 0.4 mm), an error all of a view's
  // corners share. Taken as independent per corner, unmoved cameras moved
  // 1.5 times the check's σ here (and 3.4 times on rendered cells).
  CalibrationOptions given;
  given.robot_sigma_mm = 0.1;
  given.robot_sigma_deg =
      0.01 / std::sqrt(3.0);  // per axis: the simulated turn is 0.01° about a random axis
  const CalibrationResult calibration = Calibrate(Capture(20, 0).dataset, given);
  REQUIRE(calibration.solver.robot_sigma_mm == Approx(0.1));
  CalibrationResult blind = calibration;  // as if the robot had been taken as exact
  blind.solver.robot_sigma_mm = blind.solver.robot_sigma_deg = 0;
  blind.solver.robot_sigma_solved_mm = blind.solver.robot_sigma_solved_deg = 0;
  double sum_sq = 0, blind_sum_sq = 0;
  int cameras = 0, moved = 0;
  for (std::uint64_t seed = 100; seed < 110; ++seed) {
    const Dataset later = Capture(8, seed).dataset;
    const DriftResult drift = CheckDrift(later, calibration, DriftOptions{});
    const DriftResult blind_drift = CheckDrift(later, blind, DriftOptions{});
    for (size_t i = 0; i < drift.cameras.size(); ++i) {
      const CameraDrift& c = drift.cameras[i];
      if (!c.estimated || c.sigma_mm <= 0) continue;
      ++cameras;
      moved += c.verdict == "moved";
      sum_sq += std::pow(c.moved_mm / c.sigma_mm, 2);
      blind_sum_sq +=
          std::pow(blind_drift.cameras[i].moved_mm / blind_drift.cameras[i].sigma_mm, 2);
    }
  }
  REQUIRE(cameras >= 30);
  const double rms = std::sqrt(sum_sq / cameras), blind_rms = std::sqrt(blind_sum_sq / cameras);
  INFO("moved/σ RMS " << rms << " (robot error left out: " << blind_rms << ") over " << cameras
                      << " cameras");
  CHECK(moved == 0);
  CHECK(rms > 0.7);
  CHECK(rms < 1.3);
  CHECK(blind_rms > 1.5 * rms);

  // Where held-out poses chose the exact robot over the model the views
  // suggested, the model's σ stands for the new poses' error all the same.
  CalibrationResult exact_chosen = blind;
  ModelChoice choice;
  choice.chosen = "exact robot";
  choice.folds = 4;
  choice.candidates = {{"exact robot", 0.2, 1000},
                       {"robot error modelled", 0.3, 1000, 0.1, given.robot_sigma_deg}};
  exact_chosen.solver.model = choice;
  const Dataset later = Capture(8, 100).dataset;
  const DriftResult modelled = CheckDrift(later, calibration, DriftOptions{});
  const DriftResult chosen = CheckDrift(later, exact_chosen, DriftOptions{});
  for (size_t i = 0; i < modelled.cameras.size(); ++i) {
    CHECK(chosen.cameras[i].sigma_mm == Approx(modelled.cameras[i].sigma_mm));
    CHECK(chosen.cameras[i].moved_mm == Approx(modelled.cameras[i].moved_mm));
  }
}

TEST_CASE("check takes the robot error the cameras' sigma assumes, not the solve's wide prior",
          "[drift]") {
  // The default solve on records 0.5 mm / 0.05° off: the prior it weighs them
  // with is estimated wide on purpose; the σ the solved pose blocks show is
  // what the cameras' sigma assumes, and what new poses carry.
  const CalibrationResult calibration =
      Calibrate(Capture(20, 0, "", 0.5).dataset, CalibrationOptions{});
  const SolverSummary& solver = calibration.solver;
  INFO("prior " << solver.robot_sigma_mm << " mm / " << solver.robot_sigma_deg << " deg, solved "
                << solver.robot_sigma_solved_mm << " mm / " << solver.robot_sigma_solved_deg
                << " deg");
  REQUIRE(solver.robot_sigma_solved_mm > 0);
  // σ per axis: 0.5 mm and 0.05° / √3 (the simulated turn is about a random axis).
  CHECK(solver.robot_sigma_solved_mm > 0.5 / 2);
  CHECK(solver.robot_sigma_solved_mm < 0.5 * 2);
  CHECK(solver.robot_sigma_solved_deg > 0.05 / std::sqrt(3.0) / 2);
  CHECK(solver.robot_sigma_solved_deg < 0.05 / std::sqrt(3.0) * 2);

  // The same solution under three accounts of the robot's error: the solved
  // σ beside a prior twice as wide, that σ as the only one (a result written
  // before the field), and the exact robot chosen over the models compared
  // (the solved poses' σ the last candidate).
  CalibrationResult wide = calibration, only = calibration, exact = calibration,
                    prior = calibration;
  wide.solver.robot_sigma_mm = 1.0;
  wide.solver.robot_sigma_deg = 0.06;
  wide.solver.robot_sigma_solved_mm = only.solver.robot_sigma_mm = 0.5;
  wide.solver.robot_sigma_solved_deg = only.solver.robot_sigma_deg = 0.03;
  only.solver.robot_sigma_solved_mm = only.solver.robot_sigma_solved_deg = 0;
  prior.solver = wide.solver;
  prior.solver.robot_sigma_solved_mm = prior.solver.robot_sigma_solved_deg = 0;
  exact.solver.robot_sigma_mm = exact.solver.robot_sigma_deg = 0;
  exact.solver.robot_sigma_solved_mm = exact.solver.robot_sigma_solved_deg = 0;
  ModelChoice choice;
  choice.chosen = "exact robot";
  choice.folds = 4;
  choice.candidates = {{"exact robot", 0.2, 1000},
                       {"robot error modelled", 0.3, 1000, 1.0, 0.06},
                       {"robot error modelled at the solved poses' σ", 0.25, 1000, 0.5, 0.03}};
  exact.solver.model = choice;
  const Dataset later = Capture(8, 100, "", 0.5).dataset;
  const DriftResult by_wide = CheckDrift(later, wide, DriftOptions{}),
                    by_only = CheckDrift(later, only, DriftOptions{}),
                    by_exact = CheckDrift(later, exact, DriftOptions{}),
                    by_prior = CheckDrift(later, prior, DriftOptions{});
  int wider = 0;
  for (size_t i = 0; i < by_wide.cameras.size(); ++i) {
    if (!by_wide.cameras[i].estimated) continue;
    CHECK(by_wide.cameras[i].sigma_mm == Approx(by_only.cameras[i].sigma_mm));
    CHECK(by_exact.cameras[i].sigma_mm == Approx(by_only.cameras[i].sigma_mm));
    wider += by_prior.cameras[i].sigma_mm > 1.2 * by_wide.cameras[i].sigma_mm;
  }
  CHECK(wider >= 3);
}

TEST_CASE("check's sigma holds the calibrated target's error as far as the new estimate follows it",
          "[drift]") {
  const CalibrationResult calibration = Calibrate(Capture(20, 0).dataset, CalibrationOptions{});
  REQUIRE(calibration.target_sigma);
  for (const CameraResult& camera : calibration.cameras) {
    REQUIRE(camera.sigma);
    REQUIRE(camera.sigma->covariance_with_target);  // every camera of the joint solve
  }
  // The same cameras against a target known exactly, and against one known
  // 10 times worse than solved, each apart from the cameras' errors: the
  // target held in the check moves the new estimate, and its error with it.
  CalibrationResult exact_target = calibration, poor_target = calibration;
  const PoseUncertainty& target = *calibration.target_sigma;
  exact_target.target_sigma->covariance = exact_target.target_sigma->from_given_intrinsics;
  poor_target.target_sigma->covariance =
      target.from_given_intrinsics + 100.0 * (target.covariance - target.from_given_intrinsics);
  for (CalibrationResult* r : {&exact_target, &poor_target})
    for (CameraResult& camera : r->cameras) camera.sigma->covariance_with_target->setZero();
  CalibrationResult written_before = calibration;  // without the field: the two apart
  for (CameraResult& camera : written_before.cameras) camera.sigma->covariance_with_target.reset();
  const Dataset later = Capture(8, 100).dataset;
  const DriftResult by_exact = CheckDrift(later, exact_target, DriftOptions{}),
                    by_poor = CheckDrift(later, poor_target, DriftOptions{}),
                    by_before = CheckDrift(later, written_before, DriftOptions{});
  for (size_t i = 0; i < by_exact.cameras.size(); ++i) {
    INFO(by_exact.cameras[i].name);
    REQUIRE(by_exact.cameras[i].estimated);
    CHECK(by_before.cameras[i].sigma_mm == Approx(by_exact.cameras[i].sigma_mm).epsilon(1e-9));
    CHECK(by_poor.cameras[i].sigma_mm > 1.5 * by_exact.cameras[i].sigma_mm);
    CHECK(by_poor.cameras[i].sigma_deg > by_exact.cameras[i].sigma_deg);
  }
}

TEST_CASE("check asks more than 3 sigma where the robot's sigma was estimated from the poses",
          "[drift]") {
  // The default solve estimates the robot's σ from its 20 poses, 3 degrees
  // of freedom per pose less half the 30 unknowns of 4 cameras and the
  // target: 45. A move of 3.09σ is then as likely from noise alone as one of
  // 2.94σ with σ known, so not called moved; with the same σ given it is.
  const CalibrationResult calibration =
      Calibrate(Capture(20, 0, "", 0.5).dataset, CalibrationOptions{});
  REQUIRE(calibration.solver.robot_sigma_solved_mm > 0);
  const Dataset later = Capture(8, 100, "", 0.5).dataset;
  const DriftResult quiet = CheckDrift(later, calibration, DriftOptions{});
  const CameraDrift& found = quiet.cameras[1];
  REQUIRE(found.estimated);
  // The calibrated camera put 3.09σ from where the new views find it, along x.
  CalibrationResult shifted = calibration;
  CameraResult& cam = shifted.cameras[1];
  cam.T_cam = found.T_cam;
  cam.T_cam.translation().x() += 3.09 * found.sigma_mm / 1000.0;
  CalibrationResult given = shifted;  // the same σ, given rather than estimated
  given.options.robot_sigma_mm = calibration.solver.robot_sigma_solved_mm;
  given.options.robot_sigma_deg = calibration.solver.robot_sigma_solved_deg;
  DriftOptions options;
  options.tolerance_mm = 0.01;  // every move is beyond it: the noise decides
  const CameraDrift estimated = CheckDrift(later, shifted, options).cameras[1];
  const CameraDrift known = CheckDrift(later, given, options).cameras[1];
  INFO(estimated.moved_mm << " mm at σ " << estimated.sigma_mm << " mm: " << estimated.reason);
  CHECK(estimated.moved_mm == Approx(3.09 * estimated.sigma_mm).epsilon(0.01));
  CHECK(known.sigma_mm == Approx(estimated.sigma_mm));
  CHECK(known.verdict == "moved");
  CHECK(estimated.verdict == "not_assessed");
  CHECK_THAT(estimated.reason, Catch::Matchers::Contains("3.18σ of the noise of the check") &&
                                   Catch::Matchers::Contains("from 45 degrees of freedom; ± "));
  // 2.5σ with the σ given: a hint, within a normal's 3σ.
  given.cameras[1].T_cam.translation().x() -= 0.59 * found.sigma_mm / 1000.0;
  const CameraDrift hinted = CheckDrift(later, given, options).cameras[1];
  CHECK(hinted.verdict == "not_assessed");
  CHECK_THAT(hinted.reason,
             Catch::Matchers::StartsWith("seems ") &&
                 Catch::Matchers::Contains("within 3σ of the noise of the check (± "));
}
