// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A simulated cell with projected observations (no images), for the test
// programs that link handeye_sim.

#include <cstdint>
#include <memory>
#include <random>
#include <string>

#include "handeye/core/checkerboard.h"
#include "handeye/core/evaluation.h"
#include "handeye/sim/synthetic.h"

namespace handeye::test {

/// The scene of `options` observed through a 7×`rows` checkerboard of 40 mm
/// with `noise_px` detection noise (seeded by `noise_seed`, or the scene's).
inline SyntheticScene ProjectedScene(const SceneOptions& options, double noise_px, int rows = 6,
                                     std::uint64_t noise_seed = 0) {
  SyntheticScene scene =
      MakeScene(options, std::make_shared<const CheckerboardTarget>(7, rows, 0.04));
  std::mt19937_64 rng(noise_seed ? noise_seed : options.seed);
  AddProjectedObservations(&scene, noise_px, &rng);
  return scene;
}

/// The cell `cell` ("small", "medium", ...) with `cameras` cameras and
/// `poses` robot poses, scene seed `seed`, as above.
inline SyntheticScene ProjectedScene(const std::string& cell, int cameras, int poses,
                                     std::uint64_t seed, double noise_px,
                                     Setup setup = Setup::kEyeToHand) {
  SceneOptions options;
  options.cell = cell;
  options.num_cameras = cameras;
  options.num_poses = poses;
  options.setup = setup;
  options.seed = seed;
  return ProjectedScene(options, noise_px);
}

/// The mean camera position error (mm) of a result against the simulator's
/// truth (the paper's e_t^GT, over the calibrated cameras).
inline double MeanCameraErrorMm(const CalibrationResult& result, const GroundTruth& truth) {
  return EvaluateAgainstTruth(result, truth).mean_translation_mm;
}

/// Both setups, for the tests that run each.
inline constexpr Setup kBothSetups[] = {Setup::kEyeToHand, Setup::kEyeInHand};

/// The result's camera named `name`; nullptr where it has none.
inline const CameraResult* CameraOf(const CalibrationResult& result, const std::string& name) {
  for (const CameraResult& camera : result.cameras)
    if (camera.name == name) return &camera;
  return nullptr;
}

/// Each camera's given focal length 1 % and principal point 3 px off, the
/// sign alternating between cameras (bench_uncertainty's --intrinsics-off 1/3).
inline void GiveIntrinsicsOff(Dataset* dataset) {
  for (size_t k = 0; k < dataset->cameras.size(); ++k) {
    const double sign = k % 2 == 0 ? 1.0 : -1.0;
    auto& p = dataset->cameras[k].params;
    p[0] *= 1.0 + 0.01 * sign;
    p[1] *= 1.0 + 0.01 * sign;
    p[2] += 3.0 * sign;
    p[3] -= 3.0 * sign;
  }
}

}  // namespace handeye::test
