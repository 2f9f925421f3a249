// SPDX-License-Identifier: GPL-2.0-or-later
// Cameras that detect the target worse than the others (blurred, distant,
// lower resolution): the joint solve weighs each camera by its own detection
// noise (core/src/residuals.h, CameraWeights), so the others keep their
// accuracy and their sigma.

#include <catch2/catch.hpp>
#include <memory>
#include <random>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/evaluation.h"
#include "handeye/sim/simulation.h"
#include "support/projected_scene.h"

using namespace handeye;

namespace {

// A medium cell of 4 cameras and 20 poses, exact robot, corners projected
// with 0.05 px of noise; the intrinsics taken as exact.
SyntheticScene WeightsScene(std::uint64_t seed) {
  SceneOptions options;
  options.cell = "medium";
  options.num_cameras = 4;
  options.num_poses = 20;
  options.seed = seed;
  return test::ProjectedScene(options, 0.05, 6, seed * 17 + 3);
}

// Gaussian noise of `px` per axis added to every corner camera `name` detected.
void AddNoise(Dataset* dataset, const std::string& name, double px, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, px);
  for (Observation& observation : dataset->observations)
    if (observation.camera == name)
      for (Eigen::Vector2d& p : observation.points_px) p += Eigen::Vector2d(noise(rng), noise(rng));
}

CalibrationOptions ExactIntrinsics() {
  CalibrationOptions options;
  options.intrinsics_sigma = GivenIntrinsicsSigma{0.0, 0.0};
  return options;
}

}  // namespace

TEST_CASE("one camera that detects 20 times worse leaves the others' accuracy and sigma",
          "[camera_weights]") {
  for (const std::uint64_t seed : {1, 2, 3}) {
    INFO("seed " << seed);
    const SyntheticScene scene = WeightsScene(seed);
    const std::string noisy = scene.dataset.cameras[1].name;
    Dataset blurred = scene.dataset;
    AddNoise(&blurred, noisy, 1.0, seed);
    const CalibrationResult clean = Calibrate(scene.dataset, ExactIntrinsics());
    const CalibrationResult worse = Calibrate(blurred, ExactIntrinsics());
    const Evaluation clean_error = EvaluateAgainstTruth(clean, scene.truth);
    const Evaluation worse_error = EvaluateAgainstTruth(worse, scene.truth);
    double others_clean = 0, others_worse = 0;
    for (size_t k = 0; k < clean.cameras.size(); ++k) {
      const CameraResult& a = clean.cameras[k];
      const CameraResult& b = worse.cameras[k];
      REQUIRE(a.sigma);
      REQUIRE(b.sigma);
      INFO("camera " << a.name << ": error " << clean_error.cameras[k].translation_mm << " -> "
                     << worse_error.cameras[k].translation_mm << " mm, sigma "
                     << a.sigma->position_mm << " -> " << b.sigma->position_mm << " mm");
      if (a.name == noisy) {
        // Its own sigma grows with its noise (20x the others').
        CHECK(b.sigma->position_mm > 5.0 * a.sigma->position_mm);
        continue;
      }
      // Weighed alike, the noisy camera's residuals set every camera's sigma
      // (measured before the weights: 6.7-8.0x the clean one).
      CHECK(b.sigma->position_mm < 1.5 * a.sigma->position_mm);
      CHECK(b.sigma->position_mm > a.sigma->position_mm / 1.5);
      others_clean += clean_error.cameras[k].translation_mm;
      others_worse += worse_error.cameras[k].translation_mm;
    }
    // Weighed alike, the others' errors summed 1.9x and 2.2x the clean ones
    // on seeds 1 and 2 (0.95x on seed 3).
    CHECK(others_worse < 1.5 * others_clean + 0.01 * 3);
  }
}

TEST_CASE("a rendered camera of blurred optics and a noisy sensor leaves the others' sigma",
          "[camera_weights]") {
  // Rendered and detected: camera 1 blurred 3 px with 8 grey levels of sensor
  // noise (its corners ≈ 10x the others' residuals), against the same cell
  // rendered as usual; the intrinsics given exact.
  for (const std::uint64_t seed : {4, 5}) {
    INFO("seed " << seed);
    SceneOptions options;
    options.cell = "medium";
    options.num_cameras = 4;
    options.num_poses = 20;
    options.seed = seed;
    const auto target = std::make_shared<const CheckerboardTarget>(7, 4, 0.04);
    SyntheticScene clean = MakeScene(options, target), poor = clean;
    RenderOptions render;
    render.seed = seed;
    render.every_view = false;
    DetectSimulated(&clean, render);
    render.camera_quality["cam1"] = {3.0, 8.0};
    DetectSimulated(&poor, render);
    const CalibrationResult a = Calibrate(clean.dataset, ExactIntrinsics());
    const CalibrationResult b = Calibrate(poor.dataset, ExactIntrinsics());
    for (size_t k = 0; k < a.cameras.size(); ++k) {
      INFO("camera " << a.cameras[k].name << ": rms " << a.cameras[k].rms_px << " -> "
                     << b.cameras[k].rms_px << " px, sigma " << a.cameras[k].sigma->position_mm
                     << " -> " << b.cameras[k].sigma->position_mm << " mm");
      if (a.cameras[k].name == "cam1") {
        CHECK(b.cameras[k].rms_px > 4.0 * a.cameras[k].rms_px);
        continue;
      }
      // Measured before the weights: 3.9-4.9x the clean sigma.
      CHECK(b.cameras[k].sigma->position_mm < 1.5 * a.cameras[k].sigma->position_mm);
    }
  }
}
