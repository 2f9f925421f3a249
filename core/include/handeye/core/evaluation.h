// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Errors of a calibration against ground truth: the paper's e_t^GT and
/// e_θ^GT, eq. (error1)/(error2), per camera and as their mean.

#include <string>
#include <vector>

#include "handeye/core/calibration.h"

namespace handeye {

/// Error of one camera against the truth.
struct CameraError {
  std::string name;  ///< Camera::name
  double translation_mm = 0;  ///< ‖t − t̂‖ of T_base_cam (T_ee_cam)
  double rotation_deg = 0;    ///< angle(Rᵀ R̂)
};

/// A result compared with ground truth (`handeye evaluate`).
struct Evaluation {
  std::vector<CameraError> cameras;  ///< calibrated cameras with ground truth
  double mean_translation_mm = 0;
  double mean_rotation_deg = 0;
  /// Error of the shared transform (T_ee_target / T_base_target); only when
  /// the ground truth has it.
  bool has_target_error = false;
  double target_translation_mm = 0;
  double target_rotation_deg = 0;
  std::vector<std::string> missing;  ///< result cameras without ground truth, or uncalibrated
};

/// Throws InputError when the setups differ or no camera can be compared.
Evaluation EvaluateAgainstTruth(const CalibrationResult& result, const GroundTruth& truth);

/// The ground truth in the shape of a result: every camera of `dataset` that
/// the truth has, calibrated at its true pose, and the true shared transform
/// (e.g. to compute the Cramér–Rao bound at the true values).
CalibrationResult TruthAsResult(const Dataset& dataset, const GroundTruth& truth);

}  // namespace handeye
