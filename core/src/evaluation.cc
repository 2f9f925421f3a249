// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/evaluation.h"

#include <cmath>

#include "handeye/core/error.h"
#include "handeye/core/transform.h"

namespace handeye {

Evaluation EvaluateAgainstTruth(const CalibrationResult& result, const GroundTruth& truth) {
  if (result.setup != truth.setup)
    throw InputError("", "/setup",
                     std::string("the same setup in result and ground truth; result is ") +
                         SetupName(result.setup) + ", ground truth is " + SetupName(truth.setup));
  constexpr double kRadToDeg = 180.0 / M_PI;
  Evaluation out;
  for (const CameraResult& cam : result.cameras) {
    const auto it = truth.T_cam.find(cam.name);
    if (!cam.calibrated || it == truth.T_cam.end()) {
      out.missing.push_back(cam.name);
      continue;
    }
    CameraError e;
    e.name = cam.name;
    e.translation_mm = 1000.0 * (cam.T_cam.translation() - it->second.translation()).norm();
    e.rotation_deg = kRadToDeg * RotationDistance(it->second.rotation(), cam.T_cam.rotation());
    out.mean_translation_mm += e.translation_mm;
    out.mean_rotation_deg += e.rotation_deg;
    out.cameras.push_back(e);
  }
  if (out.cameras.empty())
    throw InputError("", "", "at least one calibrated camera that the ground truth also has");
  out.mean_translation_mm /= out.cameras.size();
  out.mean_rotation_deg /= out.cameras.size();
  if (truth.has_T_target) {
    out.has_target_error = true;
    out.target_translation_mm = 1000.0 * (result.T_target.translation() - truth.T_target.translation()).norm();
    out.target_rotation_deg = kRadToDeg * RotationDistance(truth.T_target.rotation(), result.T_target.rotation());
  }
  return out;
}

CalibrationResult TruthAsResult(const Dataset& dataset, const GroundTruth& truth) {
  CalibrationResult result;
  result.setup = truth.setup;
  result.T_target = truth.T_target;
  for (const Camera& camera : dataset.cameras) {
    const auto it = truth.T_cam.find(camera.name);
    if (it == truth.T_cam.end()) continue;
    CameraResult c;
    c.name = camera.name;
    c.calibrated = true;
    c.T_cam = it->second;
    result.cameras.push_back(c);
  }
  return result;
}

}  // namespace handeye
