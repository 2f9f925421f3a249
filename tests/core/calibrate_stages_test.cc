// SPDX-License-Identifier: GPL-2.0-or-later
// The stages of Calibrate() (core/src/calibrate_stages.h) one at a time, on
// projected observations of simulated cells: what each adds to the state,
// what it refuses, and that the options are only read.
#include "calibrate_stages.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <memory>
#include <random>
#include <string>

#include "handeye/core/checkerboard.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "handeye/sim/synthetic.h"
#include "support/projected_scene.h"

using namespace handeye;
using internal::Calibration;

namespace {

SyntheticScene StageScene(int cameras, int poses, std::uint64_t seed) {
  return test::ProjectedScene("small", cameras, poses, seed, 0.1);
}

double PositionErrorMm(const Eigen::Isometry3d& T_cam_mount, const Eigen::Isometry3d& T_cam_true) {
  return 1000.0 * (T_cam_mount.inverse().translation() - T_cam_true.translation()).norm();
}

}  // namespace

TEST_CASE(
    "PrepareCameras estimates missing intrinsics for the joint solve only, and names unknown held "
    "cameras") {
  SyntheticScene scene = StageScene(2, 12, 3);
  scene.dataset.cameras[1].has_intrinsics = false;
  CalibrationOptions options;
  {
    Calibration c(scene.dataset, options);
    internal::PrepareCameras(&c);
    CHECK(c.estimated == std::vector<bool>{false, true});
    CHECK(c.start_cameras.size() == 2);
    CHECK(c.working.cameras[1].has_intrinsics);
    REQUIRE(c.result.notes.size() == 1);
    CHECK(c.result.notes[0].find("camera '" + scene.dataset.cameras[1].name +
                                 "' has no intrinsics") == 0);
    // The given dataset is read, not changed.
    CHECK_FALSE(scene.dataset.cameras[1].has_intrinsics);
  }
  options.method = Method::kPark;
  {
    Calibration c(scene.dataset, options);
    CHECK_THROWS_WITH(internal::PrepareCameras(&c),
                      Catch::Contains("only --method joint estimates them"));
  }
  scene.dataset.cameras[1].has_intrinsics = true;
  options.method = Method::kJoint;
  options.fixed_cameras["no_such_camera"] = Eigen::Isometry3d::Identity();
  Calibration c(scene.dataset, options);
  CHECK_THROWS_WITH(internal::PrepareCameras(&c), Catch::Contains("'no_such_camera' to hold"));
}

TEST_CASE("PrepareViews builds the views and stops at too few of them") {
  const SyntheticScene scene = StageScene(2, 12, 5);
  const CalibrationOptions options;
  Calibration c(scene.dataset, options);
  internal::PrepareCameras(&c);
  internal::PrepareViews(&c);
  CHECK(c.problem.views.size() == scene.dataset.observations.size());
  CHECK(c.problem.dataset == &c.working);
  CHECK(c.problem.camera_views.size() == 2);
  CHECK_FALSE(c.problem.camera_views[0].empty());

  Dataset two_poses = scene.dataset;
  two_poses.poses.resize(2);
  two_poses.observations.erase(
      std::remove_if(two_poses.observations.begin(), two_poses.observations.end(),
                     [&](const Observation& o) {
                       return o.pose_id != two_poses.poses[0].id &&
                              o.pose_id != two_poses.poses[1].id;
                     }),
      two_poses.observations.end());
  Calibration few(two_poses, options);
  internal::PrepareCameras(&few);
  CHECK_THROWS_AS(internal::PrepareViews(&few), SolveError);
}

TEST_CASE(
    "Each strategy leaves an estimate, a solver summary and a covariance per calibrated camera") {
  const SyntheticScene scene = StageScene(3, 14, 7);
  for (Method method : {Method::kJoint, Method::kPerCamera, Method::kPark}) {
    CalibrationOptions options;
    options.method = method;
    const double scale_before = options.cauchy_scale_px;
    Calibration c(scene.dataset, options);
    internal::PrepareCameras(&c);
    internal::PrepareViews(&c);
    if (method == Method::kJoint)
      internal::SolveJointMethod(&c);
    else if (method == Method::kPerCamera)
      internal::SolvePerCameraMethod(&c);
    else
      internal::SolveClosedFormMethod(&c);
    INFO(MethodName(method));
    CHECK(options.cauchy_scale_px == scale_before);  // options are read, never rewritten
    CHECK(c.est.per_camera_target == (method != Method::kJoint));
    CHECK(c.result.solver.converged);
    if (method == Method::kPark) CHECK(c.result.solver.termination == "CLOSED_FORM");
    for (size_t k = 0; k < 3; ++k) {
      REQUIRE(c.est.T_cam_mount[k]);
      const Eigen::Isometry3d& truth = scene.truth.T_cam.at(scene.dataset.cameras[k].name);
      CHECK(PositionErrorMm(*c.est.T_cam_mount[k], truth) < (method == Method::kPark ? 5.0 : 1.0));
      CHECK(c.camera_covariance.covariance.count(k) == 1);
    }
    // Only the joint solve has pair parameters; the others get theirs chained by ExplainViews.
    CHECK(c.result.camera_pairs.size() == (method == Method::kJoint ? 3u : 0u));
    internal::ExplainViews(&c);
    CHECK(c.result.camera_pairs.size() == 3);
    internal::FillResultStage(&c);
    REQUIRE(c.result.cameras.size() == 3);
    CHECK_FALSE(c.result.cameras[0].sigma);
    internal::IntrinsicsCheckAndSigma(&c);
    for (const CameraResult& camera : c.result.cameras) {
      REQUIRE(camera.sigma);
      CHECK(camera.sigma->position_mm > 0);
    }
  }
}

TEST_CASE("AtLossScale gives the round's options and leaves the given ones alone") {
  CalibrationOptions options;
  options.cauchy_scale_px = 2.0;
  const CalibrationOptions round = internal::AtLossScale(options, 7.5);
  CHECK(round.cauchy_scale_px == 7.5);
  CHECK(options.cauchy_scale_px == 2.0);
  CHECK(round.method == options.method);
  CHECK(internal::UnrefinedIntrinsics({{0, 1}, {2, 3}, {}}, 3) ==
        std::vector<unsigned>{unsigned(kPrincipalPoint), unsigned(kFocal),
                              unsigned(kFocal | kPrincipalPoint)});
}

TEST_CASE(
    "the joint solve's covariance is taken at its solution: the given intrinsics' shift stays "
    "within what their uncertainty allows") {
  // Exact intrinsics, so the views can only shift them by noise: G·δc has a
  // spread of at most the consider term G Σ_post Gᵀ. The covariance step
  // once restarted the cross terms' pairs from the cameras' own poses, where
  // the cost's gradient is far from 0; the shift read from that gradient was
  // 10-30 times the consider term's σ (camera σ of 30-90 mm at errors of 1 mm).
  for (std::uint64_t seed : {11, 12, 13}) {
    SceneOptions scene_options;
    scene_options.cell = "medium";
    scene_options.num_cameras = 5;
    scene_options.num_poses = 12;
    scene_options.seed = seed;
    scene_options.pose_noise_mm = 0.3;
    scene_options.pose_noise_deg = 0.03;
    const SyntheticScene scene = test::ProjectedScene(scene_options, 0.2);
    CalibrationOptions options;
    REQUIRE(options.cross_terms);
    Calibration c(scene.dataset, options);
    internal::PrepareCameras(&c);
    internal::PrepareViews(&c);
    internal::SolveJointMethod(&c);
    for (const auto& [k, shift] : c.camera_covariance.intrinsics_shift) {
      INFO("seed " << seed << ", camera " << k);
      const Eigen::Matrix<double, 6, 6>& consider = c.camera_covariance.from_intrinsics.at(k);
      const double spread = std::sqrt(consider.topLeftCorner<3, 3>().trace());
      CHECK(spread > 0);
      CHECK(shift.head<3>().norm() < 4.0 * spread);
    }
    CHECK(c.camera_covariance.intrinsics_shift.size() == 5);
  }
}
