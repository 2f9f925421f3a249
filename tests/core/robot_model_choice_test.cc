// SPDX-License-Identifier: GPL-2.0-or-later
// The robot model the joint solve takes by default (core/src/calibrate_joint.cc,
// ModelChosenRounds): where the views show the robot's error only a little,
// held-out poses choose between the exact robot and the modelled one.

#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/drift.h"
#include "handeye/core/evaluation.h"
#include "handeye/core/plan.h"
#include "handeye/sim/plan_cell.h"
#include "handeye/sim/render.h"
#include "handeye/sim/simulation.h"
#include "robot_error.h"
#include "support/projected_scene.h"

using namespace handeye;

namespace {

/// A cell of the simulator with the robot's pose error (mm, and deg about a random axis).
SceneOptions CellWithRobotError(const std::string& cell, int cameras, int poses, std::uint64_t seed,
                                double robot_mm, double robot_deg) {
  SceneOptions options;
  options.cell = cell;
  options.num_cameras = cameras;
  options.num_poses = poses;
  options.seed = seed;
  options.pose_noise_mm = robot_mm;
  options.pose_noise_deg = robot_deg;
  return options;
}

// A medium cell of 4 cameras and 30 poses, corners projected with 0.1 px of
// noise: at a robot error of 0.1 mm / 0.01° its chain residuals are only a
// little above PnP's.
SyntheticScene RobotModelScene(std::uint64_t seed, double robot_mm, double robot_deg) {
  return test::ProjectedScene(CellWithRobotError("medium", 4, 30, seed, robot_mm, robot_deg), 0.1,
                              4, seed * 31 + 7);
}

double MeanErrorMm(const Dataset& dataset, const CalibrationOptions& options,
                   const GroundTruth& truth, CalibrationResult* result = nullptr) {
  CalibrationResult solved = Calibrate(dataset, options);
  const double mm = test::MeanCameraErrorMm(solved, truth);
  if (result) *result = std::move(solved);
  return mm;
}

/// How many of the result's notes hold `text`.
int NotesWith(const CalibrationResult& result, const std::string& text) {
  int count = 0;
  for (const std::string& note : result.notes) count += note.find(text) != std::string::npos;
  return count;
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
    const SyntheticScene scene = RobotModelScene(seed, 0.1, 0.01);
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
    const SyntheticScene scene = RobotModelScene(seed, 0.0, 0.0);
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

TEST_CASE(
    "where the robot's error is modelled from 12 poses, the cameras' own sigma is not below their "
    "error",
    "[robot_model]") {
  // bench/plan's large cell: 6 cameras, 12 planned poses, robot 0.3 mm /
  // 0.03°. The solved cameras and target take up 7 of each record axis' 12
  // degrees of freedom; the solved poses' spread alone put the robot's σ at
  // 0.13-0.21 mm and the cameras' own σ 1.5x below their true error (RMS;
  // with the REML count 1.2x). Counted over the solves where the views
  // showed the robot's error: 3 of the 6 model it (0.98, 0.72, 1.11), in 2
  // held-out poses choose the exact robot, whose σ then carries the modelled
  // solve's robot σ as an uncertain input (1.94 and 1.85 without it, 0.84
  // and 1.14 with it); together 0.94. Left out: the one (seed 2006) whose
  // views show no robot error at all, 2.05x (an error below what the views
  // can see, which no estimate here holds).
  const auto target = std::make_shared<const CheckerboardTarget>(7, 4, 0.04);
  double error_sq = 0, sigma_sq = 0;
  int cameras = 0;
  for (const std::uint64_t seed : {2001, 2002, 2003, 2004, 2005, 2006}) {
    SceneOptions options = CellWithRobotError("large", 6, 30, seed, 0.3, 0.03);
    RoughKnowledge rough;
    rough.seed = seed;
    rough.robot_sigma_deg = 0.03 / std::sqrt(3.0);
    PlanOptions plan_options;
    plan_options.poses = 12;
    plan_options.seed = seed;
    const CapturePlan plan =
        PlanCapture(PlanCellOfScene(MakeScene(options, target), rough), plan_options);
    REQUIRE(plan.failure.empty());
    for (const PlannedPose& pose : plan.poses) options.given_poses.push_back(pose.T_base_ee);
    options.num_poses = static_cast<int>(options.given_poses.size());
    const SyntheticScene scene = test::ProjectedScene(options, 0.2, 4, seed + 7919);
    const CalibrationResult result = Calibrate(scene.dataset, CalibrationOptions{});
    const Evaluation evaluation = EvaluateAgainstTruth(result, scene.truth);
    if (!(result.solver.robot_sigma_mm > 0) && !result.solver.model) continue;
    for (const CameraError& e : evaluation.cameras)
      for (const CameraResult& c : result.cameras)
        if (c.name == e.name && c.sigma) {
          error_sq += e.translation_mm * e.translation_mm;
          sigma_sq += c.sigma->OwnPositionMm() * c.sigma->OwnPositionMm();
          ++cameras;
        }
  }
  REQUIRE(cameras >= 30);
  const double ratio = std::sqrt(error_sq / sigma_sq);
  INFO("RMS true error over RMS own sigma: " << ratio << " over " << cameras << " cameras");
  CHECK(ratio < 1.35);
  CHECK(ratio > 0.7);
}

TEST_CASE("held-out poses keep the suggested model, then the solved poses' sigma, then the best",
          "[robot_model]") {
  using internal::ModelByHeldOut;
  auto candidate = [](const char* name, double rms, int points = 100) {
    ModelCandidate c;
    c.name = name;
    c.held_out_rms_px = rms;
    c.points = points;
    return c;
  };
  auto candidates = [&](double exact, double modelled, double settled) {
    return std::vector<ModelCandidate>{
        candidate("exact robot", exact), candidate("robot error modelled", modelled),
        candidate("robot error modelled at the solved poses' σ", settled)};
  };
  const std::vector<size_t> modelled_first = {1, 2}, exact_first = {0, 2};
  // Within 5 % of the best: the suggested one stays.
  CHECK(ModelByHeldOut(candidates(0.100, 0.104, 0.120), modelled_first) == "robot error modelled");
  CHECK(ModelByHeldOut(candidates(0.104, 0.100, 0.100), exact_first) == "exact robot");
  // The suggested one out: the solved poses' σ where it predicts alike with the
  // best (a leave-out split of a rendered capture: 0.168, 0.209, 0.168) ...
  CHECK(ModelByHeldOut(candidates(0.168, 0.209, 0.168), modelled_first) ==
        "robot error modelled at the solved poses' σ");
  CHECK(ModelByHeldOut(candidates(0.175, 0.230, 0.180), modelled_first) ==
        "robot error modelled at the solved poses' σ");
  // ... else the best.
  CHECK(ModelByHeldOut(candidates(0.126, 0.163, 0.137), modelled_first) == "exact robot");
  CHECK(ModelByHeldOut(candidates(0.200, 0.100, 0.150), exact_first) == "robot error modelled");
  // Two candidates (no settled σ apart): the suggested, else the best.
  const std::vector<ModelCandidate> two = {candidate("exact robot", 0.10),
                                           candidate("robot error modelled", 0.20)};
  CHECK(ModelByHeldOut(two, {1, 1}) == "exact robot");
  CHECK(ModelByHeldOut(two, {0, 1}) == "exact robot");
  // Where the given intrinsics are found off, the exact robot first where it
  // predicts alike with the best (METRIC, split 4 of 8, seed 1: 0.0656,
  // 0.0966, 0.0661 px), but a model that predicts clearly better is kept in
  // the views' order (bench/robot-model's ChArUco cell at 0.5 mm, seed 2,
  // whose check found a focal length off that is not: 0.611, 0.444, 0.446).
  using internal::PreferredModels;
  CHECK(PreferredModels(true, false, 3) == modelled_first);
  CHECK(PreferredModels(false, false, 3) == exact_first);
  CHECK(ModelByHeldOut(candidates(0.0656, 0.0966, 0.0661), PreferredModels(true, true, 3)) ==
        "exact robot");
  CHECK(ModelByHeldOut(candidates(0.0656, 0.0966, 0.0661), PreferredModels(true, false, 3)) ==
        "robot error modelled at the solved poses' σ");
  CHECK(ModelByHeldOut(candidates(0.611, 0.444, 0.446), PreferredModels(true, true, 3)) ==
        "robot error modelled");
  // No points held out: the suggested one.
  const std::vector<ModelCandidate> none = {candidate("exact robot", 0, 0),
                                            candidate("robot error modelled", 0, 0)};
  CHECK(ModelByHeldOut(none, {1, 1}) == "robot error modelled");
}

TEST_CASE(
    "where the exact robot is chosen, a modelled robot error beyond any robot's is not carried "
    "into sigma",
    "[robot_model]") {
  // One camera, 16 poses, given without the distortion (k1 0.2) its images
  // have, as the industrial_calibration ChArUco set's camera (no distortion
  // model): the modelled solve takes the lens' misfit up as robot error
  // (6.5-7.7 mm, 0.31-0.70 deg per axis) and predicts held-out poses 2.1-3.0x
  // worse than the exact robot. That σ is no robot's; carried into the
  // exact solve's σ it had put the set's camera at 0.56-0.79 of its
  // leave-a-quarter-out spread (bench/leave-out), without it 0.77-1.01.
  for (const std::uint64_t seed : {1, 2, 3}) {
    INFO("seed " << seed);
    const SyntheticScene scene = test::ProjectedScene(
        CellWithRobotError("medium", 1, 16, seed, 0.1, 0.01), 0.2, 4, seed + 11);
    Dataset given = scene.dataset;
    given.cameras[0].params[4] -= 0.2;
    const CalibrationResult result = Calibrate(given, CalibrationOptions{});
    REQUIRE(result.solver.model);
    CHECK(result.solver.model->chosen == "exact robot");
    CHECK(NotesWith(result,
                    "more than any industrial robot's, so the misfit it took up is not "
                    "the robot's") == 1);
    const CalibrationResult exact = Calibrate(given, RobotSigma(0, 0));
    REQUIRE(result.cameras[0].sigma);
    REQUIRE(exact.cameras[0].sigma);
    CHECK(result.cameras[0].sigma->position_mm ==
          Approx(exact.cameras[0].sigma->position_mm).epsilon(0.02));
    // Still honest: the camera within 2σ of the truth (measured 0.23-0.76σ).
    const double error_mm = test::MeanCameraErrorMm(result, scene.truth);
    CHECK(error_mm < 2.0 * result.cameras[0].sigma->position_mm);
  }
}

// Named "rendered": scripts/test-sanitizers leaves out the tests that render whole cells.
TEST_CASE(
    "on a rendered cell whose given intrinsics are off, a tie of held-out poses goes to the exact "
    "robot",
    "[robot_model]") {
  // The scene of `bench_uncertainty --source images --intrinsics-off 1/3`
  // (small cell, seed 1003): an exact robot, focal lengths 1 % and principal
  // points 3 px off (even cameras +, odd −). The views suggest a robot error
  // of 1.85 mm / 0.086° per axis (the intrinsics' misfit), and held-out poses
  // cannot tell the models apart (exact 0.982 px, modelled 1.01, at the
  // solved poses' σ 0.997). Taken by order, the modelled solve put σ at
  // 58-68 mm for errors of 14-17 mm (e/σ 0.23-0.25); with the tie to the
  // exact robot, σ 14.9-16.9 mm (e/σ 0.90-0.97).
  SceneOptions options = CellWithRobotError("small", 4, 20, 1003, 0, 0);
  SyntheticScene scene = MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
  RenderOptions render;
  render.seed = options.seed * 1000003u;
  render.noise_sigma = 0.1;
  render.every_view = false;  // the views without the target add nothing here
  DetectSimulated(&scene, render);
  test::GiveIntrinsicsOff(&scene.dataset);
  const CalibrationResult result = Calibrate(scene.dataset, CalibrationOptions{});
  REQUIRE(result.solver.model);
  CHECK(result.solver.model->chosen == "exact robot");
  CHECK(NotesWith(result,
                  "the views find given intrinsics off, a misfit pose blocks would take "
                  "up, so the exact robot is preferred") == 1);
  const auto errors = EvaluateAgainstTruth(result, scene.truth);
  REQUIRE(errors.cameras.size() == 4);
  for (const auto& camera : errors.cameras) {
    const CameraResult* it = test::CameraOf(result, camera.name);
    REQUIRE(it);
    REQUIRE(it->sigma);
    INFO(camera.name << ": " << camera.translation_mm << " mm, sigma " << it->sigma->position_mm);
    // Within 2σ, and σ not four times the error.
    CHECK(camera.translation_mm < 2.0 * it->sigma->position_mm);
    CHECK(camera.translation_mm > 0.6 * it->sigma->position_mm);
  }
}

TEST_CASE(
    "where the exact robot is taken for given intrinsics found off, sigma carries the robot's own "
    "error, not the intrinsics' misfit",
    "[robot_model]") {
  // A medium cell, robot 0.1 mm / 0.01°, focal lengths 1 % and principal
  // points 3 px off. The modelled solve's pose blocks take the intrinsics'
  // misfit up as robot error; held-out poses take the exact robot. The σ
  // that exact solve carries for the robot was the modelled solve's
  // (1.2 mm / 0.075° per axis on bench/robot-model's rendered cell of this
  // kind): new poses of the unmoved cameras then moved 0.33 of the check's σ
  // (bench/leave-out, 87 checks). Solved with the intrinsics found off freed,
  // the pose blocks show the robot's own error (0.18 mm / 0.013°).
  double sum_sq = 0;
  int checked = 0;
  for (const std::uint64_t seed : {3, 4}) {
    INFO("seed " << seed);
    auto capture = [&](int poses, std::uint64_t pose_seed) {
      SceneOptions options = CellWithRobotError("medium", 4, poses, seed, 0.1, 0.01);
      options.pose_seed = pose_seed;
      SyntheticScene scene = test::ProjectedScene(options, 0.03, 4, seed * 31 + pose_seed);
      test::GiveIntrinsicsOff(&scene.dataset);
      return scene;
    };
    const SyntheticScene scene = capture(24, 0), later = capture(8, 99);
    const CalibrationResult result = Calibrate(scene.dataset, CalibrationOptions{});
    REQUIRE(result.solver.model);
    CHECK(result.solver.model->chosen == "exact robot");
    CHECK(NotesWith(result, "the views find given intrinsics off") == 1);
    const auto errors = EvaluateAgainstTruth(result, scene.truth);
    for (const auto& camera : errors.cameras) {
      const CameraResult* it = test::CameraOf(result, camera.name);
      REQUIRE(it);
      REQUIRE(it->sigma);
      INFO(camera.name << ": " << camera.translation_mm << " mm, sigma " << it->sigma->position_mm
                       << ", own " << it->sigma->OwnPositionMm());
      CHECK(camera.translation_mm < 2.0 * it->sigma->position_mm);
    }
    const DriftResult drift = CheckDrift(later.dataset, result, DriftOptions{});
    for (const CameraDrift& camera : drift.cameras) {
      if (camera.sigma_mm <= 0) continue;
      INFO(camera.name << " moved " << camera.moved_mm << " mm at sigma " << camera.sigma_mm);
      CHECK(camera.verdict != "moved");
      sum_sq += std::pow(camera.moved_mm / camera.sigma_mm, 2);
      ++checked;
    }
  }
  REQUIRE(checked >= 6);
  const double rms = std::sqrt(sum_sq / checked);
  INFO("unmoved cameras moved " << rms << " of the check's sigma (RMS)");
  CHECK(rms > 0.5);
  CHECK(rms < 1.6);
}
