// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/evaluation.h"

#include "diagnostics_internal.h"
#include "handeye/core/error.h"

namespace handeye {

Evaluation EvaluateAgainstTruth(const CalibrationResult& result, const GroundTruth& truth) {
  if (result.setup != truth.setup)
    throw InputError("", "/setup",
                     std::string("the same setup in result and ground truth; result is ") +
                         SetupName(result.setup) + ", ground truth is " + SetupName(truth.setup));
  Evaluation out;
  for (const CameraResult& cam : result.cameras) {
    const auto it = truth.T_cam.find(cam.name);
    if (!cam.calibrated || it == truth.T_cam.end()) {
      out.missing.push_back(cam.name);
      continue;
    }
    CameraError e;
    e.name = cam.name;
    const internal::PoseDifference error = internal::DifferenceOf(it->second, cam.T_cam);
    e.translation_mm = error.translation_mm;
    e.rotation_deg = error.rotation_deg;
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
    const internal::PoseDifference error = internal::DifferenceOf(truth.T_target, result.T_target);
    out.target_translation_mm = error.translation_mm;
    out.target_rotation_deg = error.rotation_deg;
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
