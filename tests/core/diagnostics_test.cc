// SPDX-License-Identifier: GPL-2.0-or-later
// The diagnostics of a calibration (handeye/core/diagnostics.h): AX = ZB in
// the frames it is stated in, warnings computed once and stored in the
// result, and figures a closed form cannot have.
// clang-format off
// Before Catch, so that CHECK is Catch's, not glog's (which Ceres' headers define).
#include "diagnostics_internal.h"
// clang-format on
#include "handeye/core/diagnostics.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "handeye/core/checkerboard.h"
#include "handeye/core/evaluation.h"
#include "handeye/sim/synthetic.h"

using namespace handeye;

namespace {

// The report tests' small cell: 4 cameras, 960 × 540.
SyntheticScene DiagnosticsScene(const std::string& cell, int poses, double noise_px) {
  SceneOptions options;
  options.cell = cell;
  options.num_cameras = 4;
  options.num_poses = poses;
  options.seed = 11;
  options.width = 960;
  options.height = 540;
  SyntheticScene scene = MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
  std::mt19937_64 rng(5);
  AddProjectedObservations(&scene, noise_px, &rng);
  return scene;
}

}  // namespace

TEST_CASE("AX=ZB in the cameras' frame leaves out the target frame's lever arm", "[diagnostics]") {
  const SyntheticScene scene = DiagnosticsScene("small", 20, 0.0);
  CalibrationResult result = TruthAsResult(scene.dataset, scene.truth);
  // cam0 turned by 0.2° about its own centre: where it sits is still right.
  Eigen::Isometry3d& T_base_cam0 = result.cameras[0].T_cam;
  T_base_cam0.linear() =
      T_base_cam0.linear() * Eigen::AngleAxisd(0.2 * M_PI / 180, Eigen::Vector3d::UnitX()).matrix();
  CalibrationOptions options;
  options.compare_closed_form = false;
  Diagnose(scene.dataset, options, &result);
  const AxzbError& turned = result.cameras[0].axzb;
  REQUIRE(turned.views >= 4);
  CHECK(turned.camera_frame_mm < 0.01);
  CHECK(turned.rotation_deg == Approx(0.2).epsilon(0.01));
  // The base origin seen from the target moves by the turn times its distance
  // from the camera (metres away in this cell).
  const double lever_m = T_base_cam0.translation().norm();
  CHECK(turned.target_frame_mm == Approx(1000 * lever_m * 0.2 * M_PI / 180).epsilon(0.1));
  for (size_t k = 1; k < result.cameras.size(); ++k) {
    CHECK(result.cameras[k].axzb.camera_frame_mm < 0.01);
    CHECK(result.cameras[k].axzb.target_frame_mm < 0.01);
  }
  CHECK(result.metrics.axzb_camera_translation_mm < result.metrics.axzb_translation_mm);
}

TEST_CASE("Calibrate stores each warning once, the options and the version", "[diagnostics]") {
  const SyntheticScene scene = DiagnosticsScene("small", 8, 0.1);
  const CalibrationResult result = Calibrate(scene.dataset, CalibrationOptions{});
  CHECK(!result.handeye_version.empty());
  CHECK(result.options.cross_terms);
  CHECK(result.options.method == Method::kJoint);
  CalibrationResult again = result;
  const std::vector<Warning> quality = Diagnose(scene.dataset, result.options, &again);
  REQUIRE(quality.size() >= 2);  // 8 poses: cameras with few views
  for (const Warning& warning : quality) {
    INFO(warning.text);
    CHECK(std::count(result.warnings.begin(), result.warnings.end(), warning) == 1);
  }
  for (size_t k = 0; k < result.cameras.size(); ++k) {
    const CameraResult& cam = result.cameras[k];
    if (!cam.calibrated) continue;
    CHECK(cam.max_px >= cam.rms_px);
    CHECK(cam.rotation_spread_deg > 10);
    REQUIRE(cam.closed_form);
    CHECK(cam.closed_form->method == "park");
    CHECK(again.cameras[k].rms_px == Approx(cam.rms_px).margin(1e-9));
  }
}

TEST_CASE("A closed form down-weights no view as an outlier", "[diagnostics]") {
  const SyntheticScene scene = DiagnosticsScene("small", 12, 0.2);
  CalibrationOptions options;
  options.method = Method::kTsai;
  const CalibrationResult result = Calibrate(scene.dataset, options);
  for (const ViewResult& view : result.views) CHECK_FALSE(view.outlier);
  for (const Warning& warning : result.warnings)
    CHECK(warning.text.find("outliers") == std::string::npos);
  // Its comparison is with Park's closed form; Park's own with Tsai's.
  auto compared_with = [](const CalibrationResult& r) {
    std::string method;
    for (const CameraResult& cam : r.cameras)
      if (cam.closed_form) method = cam.closed_form->method;
    return method;
  };
  CHECK(compared_with(result) == "park");
  options.method = Method::kPark;
  CHECK(compared_with(Calibrate(scene.dataset, options)) == "tsai");
}

TEST_CASE("evaluate measures a camera's pose error as the closed-form comparison does",
          "[diagnostics][evaluation]") {
  const SyntheticScene scene = DiagnosticsScene("small", 20, 0.2);
  const CalibrationResult joint = Calibrate(scene.dataset, CalibrationOptions{});
  CalibrationOptions park_options;
  park_options.method = Method::kPark;
  park_options.compare_closed_form = false;
  const CalibrationResult park = Calibrate(scene.dataset, park_options);
  // Both saw the same views, so the joint result's comparison ran Park on what Calibrate(park) did.
  for (const CalibrationResult* result : {&joint, &park})
    for (const ViewResult& view : result->views) REQUIRE(view.used);
  // Park's cameras as the truth: evaluate's errors of the joint result are
  // then the diagnostics' closed-form disagreement, figure for figure.
  GroundTruth truth;
  truth.setup = park.setup;
  truth.has_T_target = false;
  for (const CameraResult& cam : park.cameras)
    if (cam.calibrated) truth.T_cam[cam.name] = cam.T_cam;
  const Evaluation evaluation = EvaluateAgainstTruth(joint, truth);
  REQUIRE(evaluation.cameras.size() == joint.cameras.size());
  for (size_t k = 0; k < evaluation.cameras.size(); ++k) {
    const CameraError& error = evaluation.cameras[k];
    const CameraResult& cam = joint.cameras[k];
    INFO(cam.name);
    REQUIRE(error.name == cam.name);
    REQUIRE(cam.closed_form);
    REQUIRE(cam.closed_form->available);
    CHECK(cam.closed_form->method == "park");
    CHECK(error.translation_mm > 0.0);
    CHECK(error.translation_mm == Approx(cam.closed_form->translation_mm).epsilon(1e-12));
    CHECK(error.rotation_deg == Approx(cam.closed_form->rotation_deg).epsilon(1e-12));
  }
}

TEST_CASE("A closed-form disagreement names the closed form that failed, not the robot",
          "[diagnostics]") {
  // OpenCV 4.6's own Tsai put every camera of this cell metres off before
  // the views were limited to those it can take (closed_form.cc); the cause
  // of a disagreement is judged here on comparisons made to fail on purpose.
  SceneOptions options;
  options.cell = "small";
  options.num_cameras = 4;
  options.num_poses = 20;
  options.seed = 21;
  options.pose_noise_mm = 0.3;
  options.pose_noise_deg = 0.03;
  SyntheticScene scene = MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
  std::mt19937_64 rng(148);
  AddProjectedObservations(&scene, 0.2, &rng);
  const internal::Problem problem = internal::BuildProblem(scene.dataset, CalibrationOptions{});
  const double threshold_px = CalibrationOptions{}.warn.max_closed_form_disagreement_px;
  for (int k = 0; k < 4; ++k) {
    INFO("camera " << k);
    const Eigen::Isometry3d T_cam_mount =
        scene.truth.T_cam.at(scene.dataset.cameras[k].name).inverse();
    const Eigen::Isometry3d& T_holder_target = scene.truth.T_target;
    // Tsai now agrees with the truth on this cell: no disagreement to explain.
    const ClosedFormComparison tsai =
        internal::CompareWithClosedForm(problem, k, T_cam_mount, T_holder_target, Method::kTsai);
    CHECK(tsai.displacement_px < threshold_px);
    // A Tsai comparison that failed (thousands of pixels) against a good
    // result: ViSP (or Park) agrees with the result, so Tsai is named.
    ClosedFormComparison failed = tsai;
    failed.displacement_px = 1e4;
    const std::string cause = internal::DisagreementCause(problem, k, T_cam_mount, T_holder_target,
                                                          Method::kPark, failed, threshold_px);
    CHECK_THAT(cause, Catch::StartsWith("Tsai's closed form failed on these views: "));
    CHECK_THAT(cause, Catch::Contains("agrees with the result"));
    CHECK(cause.find("robot poses and views") == std::string::npos);
    // A result 300 mm off from a Tsai solve, against Park's closed form:
    // Park and ViSP agree with each other, so the result's own method failed.
    Eigen::Isometry3d off = T_cam_mount;
    off.translation() += Eigen::Vector3d(0.3, -0.1, 0.2);
    const ClosedFormComparison park =
        internal::CompareWithClosedForm(problem, k, off, T_holder_target, Method::kPark);
    CHECK(park.displacement_px > 20 * threshold_px);
    const std::string result_failed = internal::DisagreementCause(
        problem, k, off, T_holder_target, Method::kTsai, park, threshold_px);
    CHECK_THAT(result_failed,
               Catch::StartsWith("the closed forms of Park and ViSP agree with each other but not "
                                 "with the result: "));
    CHECK_THAT(
        result_failed,
        Catch::Contains("Tsai's closed form (the result) failed on these views, not the robot"));
    // The same result from the joint solve: the solve is the odd one out.
    const std::string solve_odd = internal::DisagreementCause(problem, k, off, T_holder_target,
                                                              Method::kJoint, park, threshold_px);
    CHECK_THAT(solve_odd, Catch::Contains("the solve, not the robot, is the odd one out"));
  }
}
