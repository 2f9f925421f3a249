// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The diagnostics of a calibration, computed in one place: per-view and
/// per-camera reprojection residuals, the paper's AX = ZB check, the robot's
/// rotation diversity per camera, the comparison with a per-camera closed form,
/// and the warnings they call for. Calibrate() fills them into its result;
/// Diagnose() computes them again for a result that was changed or loaded.

#include <string>
#include <vector>

#include "handeye/core/calibration.h"

namespace handeye {

/// Recomputes the diagnostics of `result` (its poses as they are now) on the
/// dataset's observations: every ViewResult's rms_px, max_px and outlier,
/// every calibrated camera's rms_px, max_px, outliers, axzb, rotation and
/// axis spread and closed_form (with options.compare_closed_form), and the
/// metrics. Views keep their `used` flags; each camera uses the intrinsics in
/// its CameraResult::intrinsics when it has them. Returns the warnings that
/// options.warn calls for (Calibrate() appends them to the result's warnings;
/// this function leaves `warnings` alone). Throws InputError when the result
/// does not belong to the dataset (setup or camera names differ).
std::vector<Warning> Diagnose(const Dataset& dataset, const CalibrationOptions& options,
                              CalibrationResult* result);

}  // namespace handeye
