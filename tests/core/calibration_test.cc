// SPDX-License-Identifier: GPL-2.0-or-later
// The calibration engine on synthetic observations (projected, no images):
// exact recovery without noise, recovery within the Cramér–Rao bound with
// noise, robustness to outliers, and the degenerate and partial cases.
#include <catch2/catch.hpp>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <random>
#include <set>
#include <thread>
#include <utility>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/error.h"
#include "handeye/core/evaluation.h"
#include "handeye/core/transform.h"
#include "handeye/core/uncertainty.h"
#include "handeye/sim/synthetic.h"

using namespace handeye;

namespace {

SyntheticScene CalibrationScene(int cameras, int poses, Setup setup, std::uint64_t seed, double noise_px,
                     const std::string& cell = "medium") {
  SceneOptions options;
  options.cell = cell;
  options.num_cameras = cameras;
  options.num_poses = poses;
  options.setup = setup;
  options.seed = seed;
  auto target = std::make_shared<const CheckerboardTarget>(7, 6, 0.04);
  SyntheticScene scene = MakeScene(options, target);
  std::mt19937_64 rng(seed * 7919 + 1);
  AddProjectedObservations(&scene, noise_px, &rng);
  return scene;
}

CalibrationResult CalibrateWith(const Dataset& dataset, Method method = Method::kJoint, int threads = 1) {
  CalibrationOptions options;
  options.method = method;
  options.threads = threads;
  return Calibrate(dataset, options);
}

double CameraPositionError(const CalibrationResult& result, const GroundTruth& truth, size_t k) {
  return (result.cameras[k].T_cam.translation() - truth.T_cam.at(result.cameras[k].name).translation()).norm();
}

double CameraRotationError(const CalibrationResult& result, const GroundTruth& truth, size_t k) {
  return RotationDistance(result.cameras[k].T_cam.rotation(), truth.T_cam.at(result.cameras[k].name).rotation());
}

}  // namespace

TEST_CASE("Joint solve recovers the truth exactly without noise", "[calibration]") {
  for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    const SyntheticScene scene = CalibrationScene(4, 15, setup, 3, 0.0);
    const CalibrationResult result = CalibrateWith(scene.dataset);
    INFO("setup " << SetupName(setup));
    REQUIRE(result.solver.converged);
    for (size_t k = 0; k < result.cameras.size(); ++k) {
      REQUIRE(result.cameras[k].calibrated);
      CHECK(CameraPositionError(result, scene.truth, k) < 1e-6);
      CHECK(CameraRotationError(result, scene.truth, k) < 1e-7);
    }
    CHECK((result.T_target.translation() - scene.truth.T_target.translation()).norm() < 1e-6);
    CHECK(result.metrics.rms_px < 1e-6);
    CHECK(result.metrics.axzb_translation_mm < 1e-3);
  }
}

TEST_CASE("Joint solve is within 3 sigma of the Cramér–Rao bound at 0.2 px noise", "[calibration]") {
  const double noise_px = 0.2;
  for (std::uint64_t seed : {11u, 12u, 13u}) {
    const SyntheticScene scene = CalibrationScene(4, 15, Setup::kEyeToHand, seed, noise_px);
    const CalibrationResult result = CalibrateWith(scene.dataset);
    const PositionCovariance bound = ComputePositionCovariance(scene.dataset, TruthAsResult(scene.dataset, scene.truth), noise_px);
    for (size_t k = 0; k < result.cameras.size(); ++k) {
      const std::string& name = result.cameras[k].name;
      // 3 sigma of the error's norm: sqrt of the covariance's trace.
      const double sigma_m = std::sqrt(bound.camera_position.at(name).trace());
      const double error_m = CameraPositionError(result, scene.truth, k);
      INFO("seed " << seed << " camera " << name << ": error " << error_m * 1e3 << " mm, sigma "
                   << sigma_m * 1e3 << " mm");
      CHECK(error_m <= 3.0 * sigma_m);
      const double sigma_rad = std::sqrt(bound.camera_rotation.at(name).trace());
      CHECK(CameraRotationError(result, scene.truth, k) <= 3.0 * sigma_rad);
    }
    // The residual matches the noise that was added (2 coordinates per point).
    CHECK(result.metrics.rms_px == Approx(noise_px * std::sqrt(2.0)).epsilon(0.15));
  }
}

TEST_CASE("Corrupted views move the joint result by less than 0.5 mm", "[calibration]") {
  SyntheticScene scene = CalibrationScene(4, 20, Setup::kEyeToHand, 21, 0.2);
  const CalibrationResult clean = CalibrateWith(scene.dataset);
  // 5% of the views: half get one corner moved by 20 px, half a wrong robot pose
  // (a different pose's images attributed to it is emulated by perturbing the pose).
  auto& observations = scene.dataset.observations;
  const size_t corrupted = std::max<size_t>(2, observations.size() / 20);
  std::mt19937_64 rng(5);
  std::set<std::string> wrong_poses;
  for (size_t c = 0; c < corrupted; ++c) {
    Observation& obs = observations[(c * 7919) % observations.size()];
    if (c % 2 == 0) {
      obs.points_px[rng() % obs.points_px.size()] += Eigen::Vector2d(20.0, 0.0);
    } else if (wrong_poses.insert(obs.pose_id).second) {
      // Wrong robot pose for every camera that saw it: 30 mm and 3° off.
      auto& pose = scene.dataset.poses[scene.dataset.PoseIndex(obs.pose_id)];
      pose.T_base_ee = pose.T_base_ee * MakeTransformFromRotationVector({0.05, 0.0, 0.0}, {0.03, 0.0, 0.0});
    }
  }
  const CalibrationResult dirty = CalibrateWith(scene.dataset);
  for (size_t k = 0; k < clean.cameras.size(); ++k) {
    const double moved = (dirty.cameras[k].T_cam.translation() - clean.cameras[k].T_cam.translation()).norm();
    INFO("camera " << clean.cameras[k].name << " moved " << moved * 1e3 << " mm");
    CHECK(moved < 0.5e-3);
  }
  // The views of the poses with a wrong record are left out and named; the
  // single moved corners are down-weighted by the loss.
  for (const auto& v : dirty.views) {
    if (!wrong_poses.count(v.pose_id)) continue;
    INFO("view " << v.pose_id << "/" << v.camera);
    CHECK_FALSE(v.used);
    CHECK_FALSE(v.rejected_because.empty());
  }
}

TEST_CASE("Degenerate motion is reported as a SolveError that says what to add", "[calibration]") {
  SyntheticScene scene = CalibrationScene(2, 8, Setup::kEyeToHand, 4, 0.0);
  // Every robot pose with the same orientation: no rotation between views.
  for (auto& pose : scene.dataset.poses) pose.T_base_ee.linear() = scene.dataset.poses[0].T_base_ee.rotation();
  try {
    CalibrateWith(scene.dataset);
    FAIL("expected a SolveError");
  } catch (const SolveError& e) {
    CHECK(std::string(e.what()).find("degenerate robot motion") != std::string::npos);
    CHECK(std::string(e.what()).find("add poses") != std::string::npos);
  }
}

TEST_CASE("A camera that never sees the target is reported, one seen once is calibrated", "[calibration]") {
  SyntheticScene scene = CalibrationScene(4, 15, Setup::kEyeToHand, 8, 0.0);
  auto& obs = scene.dataset.observations;
  const std::string blind = scene.dataset.cameras[3].name;
  const std::string once = scene.dataset.cameras[2].name;
  obs.erase(std::remove_if(obs.begin(), obs.end(), [&](const Observation& o) { return o.camera == blind; }),
            obs.end());
  bool kept = false;
  obs.erase(std::remove_if(obs.begin(), obs.end(),
                           [&](const Observation& o) {
                             if (o.camera != once) return false;
                             if (kept) return true;
                             kept = true;
                             return false;
                           }),
            obs.end());
  REQUIRE(kept);
  const CalibrationResult result = CalibrateWith(scene.dataset);
  CHECK_FALSE(result.cameras[3].calibrated);
  int warned = 0;
  for (const Warning& w : result.warnings) {
    if (w.text.find(blind) == std::string::npos) continue;
    ++warned;
    CHECK(w.kind == WarningKind::kCameraNotSeen);
    CHECK(w.camera == blind);
  }
  CHECK(warned == 1);
  REQUIRE(result.cameras[2].calibrated);
  CHECK(result.cameras[2].views == 1);
  CHECK(CameraPositionError(result, scene.truth, 2) < 1e-6);
}

TEST_CASE("One to eight cameras", "[calibration]") {
  for (int cameras : {1, 2, 8}) {
    const SyntheticScene scene = CalibrationScene(cameras, 12, Setup::kEyeToHand, 30 + cameras, 0.0);
    const CalibrationResult result = CalibrateWith(scene.dataset);
    INFO(cameras << " cameras");
    for (size_t k = 0; k < result.cameras.size(); ++k)
      if (result.cameras[k].calibrated) CHECK(CameraPositionError(result, scene.truth, k) < 1e-6);
  }
}

// One camera looking at the target, robot poses that tilt it by at most
// `max_tilt_deg` about random axes: the moderate motions every closed form
// (Tsai's included, which degenerates near 180°) handles exactly.
Dataset ModerateMotionDataset(double max_tilt_deg, GroundTruth* truth) {
  std::string why;
  Dataset d;
  d.setup = Setup::kEyeToHand;
  d.target = std::make_shared<const CheckerboardTarget>(7, 6, 0.04);
  d.cameras.push_back(*Camera::Make("cam0", 1920, 1080, 1400, 1400, 960, 540, {-0.1, 0.02, 0, 0, 0}, &why));
  // Camera 2 m in front of the robot, looking back at it (optical z along -x of base).
  Eigen::Matrix3d R_base_cam;
  R_base_cam << 0, 0, -1, 1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T_base_cam = Eigen::Isometry3d::Identity();
  T_base_cam.linear() = R_base_cam;
  T_base_cam.translation() = Eigen::Vector3d(2.0, 0.1, 1.2);
  const Eigen::Isometry3d T_ee_target = MakeTransformFromRotationVector({0.1, -0.2, 0.3}, {0.02, -0.03, 0.1});
  truth->T_cam["cam0"] = T_base_cam;
  truth->T_target = T_ee_target;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int j = 0; j < 12; ++j) {
    // Target facing the camera (its +z away from it), tilted and shifted.
    Eigen::Isometry3d T_cam_target = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d axis = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    T_cam_target.linear() = Eigen::AngleAxisd(max_tilt_deg * M_PI / 180 * std::abs(unit(rng)), axis).toRotationMatrix();
    T_cam_target.translation() = Eigen::Vector3d(0.2 * unit(rng) - 0.12, 0.1 * unit(rng) - 0.1, 1.8 + 0.2 * unit(rng));
    RobotPose pose;
    pose.id = std::to_string(j);
    pose.T_base_ee = T_base_cam * T_cam_target * T_ee_target.inverse();
    d.poses.push_back(pose);
    Observation obs;
    obs.pose_id = pose.id;
    obs.camera = "cam0";
    for (const auto& p : d.target->Points()) {
      obs.ids.push_back(p.id);
      obs.points_px.push_back(*d.cameras[0].Project(T_cam_target * p.p_target));
    }
    d.observations.push_back(obs);
  }
  return d;
}

TEST_CASE("Every method recovers noise-free data from moderate motions", "[calibration]") {
  GroundTruth truth;
  const Dataset dataset = ModerateMotionDataset(35.0, &truth);
  for (const std::string& name : MethodNames()) {
    const CalibrationResult result = CalibrateWith(dataset, *ParseMethod(name));
    INFO("method " << name);
    REQUIRE(result.cameras[0].calibrated);
    // Closed forms are exact on exact data up to their numerics.
    CHECK(CameraPositionError(result, truth, 0) < 1e-6);
    CHECK(CameraRotationError(result, truth, 0) < 1e-7);
    CHECK((result.T_target.translation() - truth.T_target.translation()).norm() < 1e-6);
  }
}

TEST_CASE("Baselines with large motions: exact or reported, never NaN", "[calibration]") {
  // Views on a camera ring differ by up to 180°, where OpenCV's Tsai, Horaud
  // and Daniilidis lose accuracy (the paper's tables show the same): their
  // output must still be a finite rigid transform or a clear failure.
  const SyntheticScene scene = CalibrationScene(3, 12, Setup::kEyeToHand, 9, 0.0);
  for (const std::string& name : MethodNames()) {
    INFO("method " << name);
    CalibrationResult result;
    try {
      result = CalibrateWith(scene.dataset, *ParseMethod(name));
    } catch (const SolveError& e) {
      CHECK(std::string(e.what()).find(name) != std::string::npos);
      continue;
    }
    for (size_t k = 0; k < result.cameras.size(); ++k) {
      if (!result.cameras[k].calibrated) continue;
      CHECK(result.cameras[k].T_cam.matrix().allFinite());
      CHECK(OrthonormalityError(result.cameras[k].T_cam.rotation()) < 1e-9);
      if (name != "tsai" && name != "horaud" && name != "daniilidis")
        CHECK(CameraPositionError(result, scene.truth, k) < 1e-6);
    }
  }
}

TEST_CASE("Method names round trip", "[calibration]") {
  for (const std::string& name : MethodNames()) CHECK(MethodName(*ParseMethod(name)) == name);
  CHECK_FALSE(ParseMethod("bogus"));
}

namespace {

// The file that descriptor 1 refers to, or nullopt when it is closed.
std::optional<std::pair<dev_t, ino_t>> StdoutFile() {
  struct stat st {};
  if (fstat(STDOUT_FILENO, &st) != 0) return std::nullopt;
  return std::make_pair(st.st_dev, st.st_ino);
}

bool StdoutWritable() {
  const int flags = fcntl(STDOUT_FILENO, F_GETFL);
  return fcntl(STDOUT_FILENO, F_GETFD) != -1 && flags != -1 &&
         ((flags & O_ACCMODE) == O_WRONLY || (flags & O_ACCMODE) == O_RDWR);
}

}  // namespace

TEST_CASE("Concurrent calibrations leave stdout open and agree", "[calibration][reentrancy]") {
  // Each call used to point fd 1 at /dev/null and back; two at once could
  // restore each other's /dev/null and silence the process for good.
  const SyntheticScene scene = CalibrationScene(2, 12, Setup::kEyeToHand, 41, 0.1);
  const auto stdout_before = StdoutFile();
  REQUIRE(stdout_before);
  for (Method method : {Method::kJoint, Method::kPerCamera, Method::kVisp}) {
    INFO("method " << MethodName(method));
    const Dataset first_copy = scene.dataset, second_copy = scene.dataset;
    CalibrationResult first, second;
    // Two threads each: the setup checks' closed forms run on both.
    std::thread first_thread([&] { first = CalibrateWith(first_copy, method, 2); });
    std::thread second_thread([&] { second = CalibrateWith(second_copy, method, 2); });
    first_thread.join();
    second_thread.join();

    CHECK(StdoutWritable());
    CHECK(StdoutFile() == stdout_before);
    REQUIRE(first.cameras.size() == second.cameras.size());
    for (size_t k = 0; k < first.cameras.size(); ++k) {
      REQUIRE(first.cameras[k].calibrated);
      REQUIRE(second.cameras[k].calibrated);
      CHECK(first.cameras[k].T_cam.isApprox(second.cameras[k].T_cam, 1e-12));
      // A sanity bound (ViSP's closed form at 0.1 px is off by ~1 mm);
      // accuracy is what the tests above check.
      CHECK(CameraPositionError(first, scene.truth, k) < 5e-3);
    }
    CHECK(first.T_target.isApprox(second.T_target, 1e-12));
  }
}

TEST_CASE("No method writes to stdout, and stdout works after ViSP's", "[calibration][reentrancy]") {
  const SyntheticScene scene = CalibrationScene(2, 12, Setup::kEyeToHand, 42, 0.1);
  // Point fd 1 at a file for the calls, then put the test's stdout back.
  std::fflush(stdout);
  std::FILE* capture = std::tmpfile();
  REQUIRE(capture);
  const int saved = dup(STDOUT_FILENO);
  REQUIRE(saved >= 0);
  REQUIRE(dup2(fileno(capture), STDOUT_FILENO) >= 0);
  const auto captured_file = StdoutFile();
  // ViSP prints through printf and std::cout; it is also an initialisation
  // candidate of the joint and per-camera methods, and the setup checks run
  // it on several threads at once.
  for (Method method : {Method::kJoint, Method::kPerCamera, Method::kVisp})
    CalibrateWith(scene.dataset, method, 2);
  std::cout.flush();
  std::fflush(stdout);
  std::fseek(capture, 0, SEEK_END);
  const long silent_size = std::ftell(capture);
  // Both streams reach fd 1 again afterwards.
  std::printf("c");
  std::cout << "++";
  std::cout.flush();
  std::fflush(stdout);
  // fd 1 must still be the capture file when the calls have returned.
  const bool still_captured = StdoutFile() == captured_file;
  dup2(saved, STDOUT_FILENO);
  close(saved);
  CHECK(still_captured);
  CHECK(silent_size == 0);
  std::fseek(capture, 0, SEEK_END);
  CHECK(std::ftell(capture) == 3);
  std::fclose(capture);
}
