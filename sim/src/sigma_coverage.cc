// SPDX-License-Identifier: GPL-2.0-or-later
// How honest the joint solve's σ is over simulated cells (synthetic.h).
#include <cmath>
#include <exception>
#include <memory>
#include <random>
#include <string>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/transform.h"
#include "handeye/sim/synthetic.h"

namespace handeye {

SigmaCoverage MeasureSigmaCoverage(SceneOptions options, double noise_px, int seeds, std::uint64_t first_seed,
                                   const CalibrationOptions& calibration) {
  SigmaCoverage out;
  for (int i = 0; i < seeds; ++i) {
    options.seed = first_seed + i;
    SyntheticScene scene = MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
    std::mt19937_64 rng(options.seed * 17 + 3);
    AddProjectedObservations(&scene, noise_px, &rng);
    CalibrationResult result;
    try {
      result = Calibrate(scene.dataset, calibration);
    } catch (const std::exception& e) {
      out.failures.push_back(options.cell + " seed " + std::to_string(options.seed) + ": " + e.what());
      continue;
    }
    AddToCoverage(result, scene.truth, &out);
  }
  return out;
}

void AddToCoverage(const CalibrationResult& result, const GroundTruth& truth, SigmaCoverage* out) {
  ++out->scenes;
  out->robot_sigma_mm.push_back(result.solver.robot_sigma_mm);
  out->robot_sigma_deg.push_back(result.solver.robot_sigma_deg);
  for (const CameraResult& camera : result.cameras) {
    if (!camera.calibrated || !camera.sigma) continue;
    const Eigen::Isometry3d& T = truth.T_cam.at(camera.name);
    const double e_t = 1000.0 * (camera.T_cam.translation() - T.translation()).norm();
    const double e_r = RotationDistance(camera.T_cam.rotation(), T.rotation()) * 180.0 / M_PI;
    ++out->cameras;
    out->position_within_2sigma += e_t <= 2.0 * camera.sigma->position_mm ? 1 : 0;
    out->rotation_within_2sigma += e_r <= 2.0 * camera.sigma->rotation_deg ? 1 : 0;
    out->position_error_mm.push_back(e_t);
    out->position_sigma_mm.push_back(camera.sigma->position_mm);
  }
}

}  // namespace handeye
