// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// `handeye-result/1` (SPEC §6): the calibration result, written atomically.

#include <string>

#include "handeye/core/calibration.h"

namespace handeye {

/// Writes the result. Camera transforms are T_base_cam (eye_to_hand) or
/// T_ee_cam (eye_in_hand), with summaries in mm and degrees; the shared
/// transform is T_ee_target or T_base_target. Never writes NaN: a camera that
/// was not calibrated has `"calibrated": false` and no transform.
void SaveResult(const CalibrationResult& result, const std::string& path);

/// The text SaveResult writes, for callers that keep it in memory (the
/// Python module's `Result.to_json()`).
std::string ResultJson(const CalibrationResult& result);

/// Reads a result written by SaveResult. Throws InputError naming the file,
/// the JSON path and what was expected.
CalibrationResult LoadResult(const std::string& path);

}  // namespace handeye
