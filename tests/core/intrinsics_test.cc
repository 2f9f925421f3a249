// SPDX-License-Identifier: GPL-2.0-or-later
// Intrinsics nobody fully trusts: factory values 1 % off, a camera given
// none, views too few to tell; the check after a default solve.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <map>
#include <random>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/error.h"
#include "handeye/core/evaluation.h"
#include "handeye/sim/synthetic.h"
#include "support/projected_scene.h"

using namespace handeye;
using Catch::Matchers::Contains;

namespace {

// A medium cell as a real capture gives it: robot pose error, detection noise.
SyntheticScene IntrinsicsScene(std::uint64_t seed, int poses, double robot_mm = 0.1, double robot_deg = 0.01) {
  SceneOptions options;
  options.cell = "medium";
  options.num_cameras = 4;
  options.num_poses = poses;
  options.seed = seed;
  options.pose_noise_mm = robot_mm;
  options.pose_noise_deg = robot_deg;
  SyntheticScene scene = MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
  std::mt19937_64 rng(seed * 31 + 7);
  AddProjectedObservations(&scene, 0.1, &rng);
  return scene;
}

// Factory intrinsics: focal length 1 % off, principal point a few pixels off,
// alternately in both directions.
Dataset WithFactoryIntrinsics(const Dataset& dataset, double k1_error = 0.0) {
  Dataset out = dataset;
  for (size_t k = 0; k < out.cameras.size(); ++k) {
    const double s = k % 2 == 0 ? 1.0 : -1.0;
    auto& p = out.cameras[k].params;
    p[0] *= 1.0 + 0.01 * s;
    p[1] *= 1.0 + 0.01 * s;
    p[2] += 3.0 * s;
    p[3] -= 2.0 * s;
    p[4] += k1_error * s;
  }
  return out;
}

int WarningsContaining(const CalibrationResult& result, const std::string& text) {
  int n = 0;
  for (const Warning& w : result.warnings) n += w.text.find(text) != std::string::npos ? 1 : 0;
  return n;
}

}  // namespace

TEST_CASE("Intrinsics lists parse", "[intrinsics]") {
  std::string why;
  CHECK(ParseIntrinsicsGroups("focal", &why) == unsigned(kFocal));
  CHECK(ParseIntrinsicsGroups("principal_point,focal", &why) == unsigned(kFocal | kPrincipalPoint));
  CHECK(ParseIntrinsicsGroups("all", &why) == unsigned(kAllIntrinsics));
  CHECK_FALSE(ParseIntrinsicsGroups("focus", &why));
  CHECK_THAT(why, Contains("focal, principal_point, distortion or all") && Contains("'focus'"));
  CHECK_FALSE(ParseIntrinsicsGroups("", &why));
  CalibrationOptions options;
  options.method = Method::kPark;
  options.refine_intrinsics = kFocal;
  CHECK_FALSE(options.Check(&why));
  CHECK_THAT(why, Contains("joint"));
}

TEST_CASE("Intrinsics 1 % off: the default solve warns, the refined one recovers", "[intrinsics]") {
  // The check's threshold is 3σ per parameter: with the true intrinsics, a
  // false alarm on one camera in eight is seen (seed 2, cam1: cx 5 px off,
  // 3.5σ); more would mean σ is too small.
  int false_alarms = 0;
  for (std::uint64_t seed : {1, 2}) {
    const SyntheticScene scene = IntrinsicsScene(seed, 30);
    CalibrationOptions options;
    const CalibrationResult exact = Calibrate(scene.dataset, options);
    const double exact_mm = test::MeanCameraErrorMm(exact, scene.truth);
    false_alarms += WarningsContaining(exact, "the images suggest");

    const Dataset factory = WithFactoryIntrinsics(scene.dataset);
    const CalibrationResult off = Calibrate(factory, options);
    const double off_mm = test::MeanCameraErrorMm(off, scene.truth);
    // Every camera is named, with the flag to use.
    CHECK(WarningsContaining(off, "--refine-intrinsics") == 4);
    CHECK(WarningsContaining(off, "fx, fy ≈") >= 3);
    CHECK(WarningsContaining(off, "which its sigma includes") == 4);
    // The bias the given intrinsics cause is in each camera's σ: the error
    // (10–30 mm) lies within 2σ, and σ is not uselessly wide.
    const auto errors = EvaluateAgainstTruth(off, scene.truth);
    for (const auto& camera : errors.cameras) {
      const CameraResult* it = test::CameraOf(off, camera.name);
      REQUIRE(it);
      REQUIRE(it->sigma);
      INFO(camera.name << ": error " << camera.translation_mm << " mm, sigma "
                       << it->sigma->position_mm << " mm");
      CHECK(camera.translation_mm < 2.0 * it->sigma->position_mm);
      CHECK(it->sigma->position_mm < 3.0 * camera.translation_mm);
    }

    options.refine_intrinsics = kFocal | kPrincipalPoint;
    const CalibrationResult refined = Calibrate(factory, options);
    const double refined_mm = test::MeanCameraErrorMm(refined, scene.truth);
    std::printf("seed %d: true intrinsics %.3f mm, 1 %% off %.2f mm, refined %.3f mm\n", int(seed), exact_mm,
                off_mm, refined_mm);
    // What 30 poses tell about each camera's focal length (σ ≈ 2 px, 0.15 %)
    // bounds the refined solve: 2.1-2.7 mm where the true intrinsics give
    // 0.27-0.31 (2.8-3.0 and 0.48-0.62 with the robot taken as exact).
    CHECK(off_mm > 10.0);
    CHECK(refined_mm < 0.15 * off_mm);
    CHECK(refined_mm < 3.0);
    CHECK(exact_mm < 0.4);
    CHECK(WarningsContaining(refined, "the images suggest") == 0);
    // The refined values lie within 4σ of the truth, and σ is not uselessly wide.
    for (size_t k = 0; k < refined.cameras.size(); ++k) {
      const auto& intrinsics = refined.cameras[k].intrinsics;
      REQUIRE(intrinsics);
      CHECK(intrinsics->refined == std::vector<std::string>{"fx", "fy", "cx", "cy"});
      for (int p = 0; p < 4; ++p) {
        INFO("camera " << k << " parameter " << Camera::ParamName(p));
        CHECK(std::abs(intrinsics->camera.params[p] - scene.dataset.cameras[k].params[p]) <
              4.0 * intrinsics->sigma[p]);
        CHECK(intrinsics->sigma[p] > 0.0);
        CHECK(intrinsics->sigma[p] < 3.0);
      }
      CHECK(intrinsics->sigma[4] == 0.0);  // k1 held
    }
  }
  CHECK(false_alarms <= 1);
}

TEST_CASE("Distortion k1 off by 0.02: refining all intrinsics recovers it", "[intrinsics]") {
  const SyntheticScene scene = IntrinsicsScene(3, 30);
  const Dataset factory = WithFactoryIntrinsics(scene.dataset, 0.02);
  CalibrationOptions options;
  const double off_mm = test::MeanCameraErrorMm(Calibrate(factory, options), scene.truth);
  options.refine_intrinsics = kAllIntrinsics;
  const CalibrationResult refined = Calibrate(factory, options);
  const double refined_mm = test::MeanCameraErrorMm(refined, scene.truth);
  std::printf("k1 off: %.2f mm, refined %.3f mm\n", off_mm, refined_mm);
  CHECK(refined_mm < 0.15 * off_mm);
  for (size_t k = 0; k < refined.cameras.size(); ++k) {
    const auto& intrinsics = refined.cameras[k].intrinsics;
    REQUIRE(intrinsics);
    const double truth = scene.dataset.cameras[k].params[4];
    INFO("camera " << k << " k1 " << intrinsics->camera.params[4] << " ± " << intrinsics->sigma[4] << ", true "
                   << truth);
    CHECK(std::abs(intrinsics->camera.params[4] - truth) < std::max(4.0 * intrinsics->sigma[4], 0.002));
  }
}

TEST_CASE("A camera without intrinsics: estimated from its views in the joint solve", "[intrinsics]") {
  const SyntheticScene scene = IntrinsicsScene(4, 30);
  CalibrationOptions options;
  const double exact_mm = test::MeanCameraErrorMm(Calibrate(scene.dataset, options), scene.truth);
  Dataset none = scene.dataset;
  for (Camera& camera : none.cameras) {
    camera.has_intrinsics = false;
    camera.params.fill(0.0);
    camera.params[0] = camera.params[1] = 2000.0;
  }
  const CalibrationResult estimated = Calibrate(none, options);
  const double estimated_mm = test::MeanCameraErrorMm(estimated, scene.truth);
  std::printf("without intrinsics: %.3f mm (true intrinsics %.3f mm)\n", estimated_mm, exact_mm);
  CHECK(estimated_mm < 6.0 * exact_mm);
  CHECK(estimated_mm < 2.5);
  for (size_t k = 0; k < estimated.cameras.size(); ++k) {
    const auto& intrinsics = estimated.cameras[k].intrinsics;
    REQUIRE(intrinsics);
    CHECK(intrinsics->refined.size() >= 8);
    for (int p = 0; p < 4; ++p) {
      INFO("camera " << k << " parameter " << Camera::ParamName(p) << " ± " << intrinsics->sigma[p]);
      CHECK(std::abs(intrinsics->camera.params[p] - scene.dataset.cameras[k].params[p]) <
            4.0 * intrinsics->sigma[p]);
    }
    CHECK(std::abs(intrinsics->camera.fx() / scene.dataset.cameras[k].fx() - 1.0) < 0.005);
  }
}

TEST_CASE("A camera without intrinsics and too few views exits with advice", "[intrinsics]") {
  SyntheticScene scene = IntrinsicsScene(5, 30);
  Dataset none = scene.dataset;
  none.cameras[1].has_intrinsics = false;
  // Keep two of cam1's views.
  std::vector<Observation> kept;
  int cam1 = 0;
  for (const Observation& obs : none.observations)
    if (obs.camera != none.cameras[1].name || ++cam1 <= 2) kept.push_back(obs);
  none.observations = kept;
  try {
    Calibrate(none, CalibrationOptions{});
    FAIL("no error");
  } catch (const SolveError& e) {
    CHECK_THAT(e.what(), Contains(none.cameras[1].name) && Contains("too few") && Contains("intrinsics"));
  }
  CalibrationOptions park;
  park.method = Method::kPark;
  none.cameras[1].has_intrinsics = false;
  CHECK_THROWS_AS(Calibrate(none, park), InputError);
}

namespace {

/// One camera of the medium cell, the target shown at `poses` flange positions
/// of the simulator's sampler, every one turned as the first pose the camera
/// sees, then by a random turn of up to `spread_deg`: views at varied places
/// and depths but hardly varied tilts.
SyntheticScene AlikeViewsScene(std::uint64_t seed, int poses, double spread_deg) {
  SceneOptions options;
  options.cell = "medium";
  options.num_cameras = 1;
  options.num_poses = poses;
  options.seed = seed;
  const auto target = std::make_shared<const CheckerboardTarget>(7, 4, 0.04);
  const SyntheticScene sampler = MakeScene(options, target);
  Eigen::Matrix3d R0 = Eigen::Matrix3d::Identity();
  for (const auto& pose : sampler.truth.poses)
    if (!pose.points_px.empty()) {
      R0 = pose.T_base_ee_true.linear();
      break;
    }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> turn(-spread_deg * M_PI / 180.0,
                                              spread_deg * M_PI / 180.0);
  for (const auto& pose : sampler.truth.poses) {
    Eigen::Isometry3d T = pose.T_base_ee_true;
    T.linear() = R0 * (Eigen::AngleAxisd(turn(rng), Eigen::Vector3d::UnitX()) *
                       Eigen::AngleAxisd(turn(rng), Eigen::Vector3d::UnitY()))
                          .toRotationMatrix();
    options.given_poses.push_back(T);
  }
  options.pose_noise_mm = 0.1;
  options.pose_noise_deg = 0.01;
  SyntheticScene scene = MakeScene(options, target);
  std::mt19937_64 noise(seed * 31 + 7);
  AddProjectedObservations(&scene, 0.1, &noise);
  return scene;
}

}  // namespace

TEST_CASE("A camera without intrinsics whose views alone barely fix them: the robot's motions do",
          "[intrinsics]") {
  // Tilts within ± 4°: OpenCV's calibration from these views alone gave
  // fx ± 100–150 px and cx, cy ± 17–80 px (above 5 %: refused before), the
  // solve with the robot's motions fx ± 1–3 px.
  for (std::uint64_t seed : {1, 2, 3}) {
    const SyntheticScene scene = AlikeViewsScene(seed, 30, 4.0);
    Dataset none = scene.dataset;
    none.cameras[0].has_intrinsics = false;
    const CalibrationResult estimated = Calibrate(none, CalibrationOptions{});
    CHECK(
        std::count_if(estimated.notes.begin(), estimated.notes.end(), [](const std::string& note) {
          return note.find("its views alone determine them only weakly") != std::string::npos;
        }) == 1);
    const CameraResult& camera = estimated.cameras[0];
    REQUIRE(camera.intrinsics);
    REQUIRE(camera.sigma);
    const double error_mm = test::MeanCameraErrorMm(estimated, scene.truth);
    INFO("seed " << seed << ": " << error_mm << " mm at σ " << camera.sigma->position_mm << " mm");
    CHECK(error_mm < 2.0 * camera.sigma->position_mm);
    for (int p = 0; p < 4; ++p) {
      INFO(Camera::ParamName(p) << " " << camera.intrinsics->camera.params[p] << " ± "
                                << camera.intrinsics->sigma[p] << ", true "
                                << scene.dataset.cameras[0].params[p]);
      CHECK(camera.intrinsics->sigma[p] <
            (p < 2 ? 0.005 * scene.dataset.cameras[0].params[p] : 10.0));
      CHECK(std::abs(camera.intrinsics->camera.params[p] - scene.dataset.cameras[0].params[p]) <
            4.0 * camera.intrinsics->sigma[p]);
    }
  }
}

TEST_CASE(
    "A camera's views that fit worse than its others do not make the check call its intrinsics off",
    "[intrinsics]") {
  // Two views of one camera whose corners are off together (turned 0.3° and
  // scaled 0.3 % about their centre, several times the others' residuals: a target
  // partly hidden or blurred, as bench/leave-out's rendered ChArUco cells
  // have), kept in the solve, the robot poses given as exact. The camera's
  // own fit weighs each view of a noise of its own by it; weighed alike, one
  // of the three seeds was warned of intrinsics off (the given values are
  // the true ones), and a principal point truly off is still found.
  int warned = 0, found = 0;
  for (std::uint64_t seed : {1, 2, 3}) {
    SyntheticScene scene = test::ProjectedScene("medium", 4, 30, seed, 0.02);
    Dataset& dataset = scene.dataset;
    // The camera with most views, and two of them.
    std::map<std::string, std::vector<size_t>> views;
    for (size_t i = 0; i < dataset.observations.size(); ++i)
      views[dataset.observations[i].camera].push_back(i);
    const auto most = std::max_element(
        views.begin(), views.end(),
        [](const auto& a, const auto& b) { return a.second.size() < b.second.size(); });
    const std::string camera = most->first;
    REQUIRE(most->second.size() >= 8);
    for (size_t n : {size_t{1}, most->second.size() / 2}) {
      Observation& view = dataset.observations[most->second[n]];
      Eigen::Vector2d centre = Eigen::Vector2d::Zero();
      for (const auto& p : view.points_px) centre += p / static_cast<double>(view.points_px.size());
      const Eigen::Matrix2d turn =
          1.003 * Eigen::Rotation2Dd(0.3 * M_PI / 180.0).toRotationMatrix();
      for (auto& p : view.points_px) p = centre + turn * (p - centre);
    }
    CalibrationOptions options;
    options.reject_views = false;
    options.robot_sigma_mm = options.robot_sigma_deg = 0;
    warned += WarningsContaining(Calibrate(dataset, options), "the images suggest");
    // A given principal point 3 px off is still found, those views in.
    Dataset off = dataset;
    off.cameras[dataset.CameraIndex(camera)].params[2] += 3.0;
    found += WarningsContaining(Calibrate(off, options),
                                "camera '" + camera + "': the images suggest cx");
  }
  CHECK(warned == 0);
  CHECK(found == 3);
}
