// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Advice after a (partial) capture (`handeye advise`): which cameras are
/// above the goal, and which poses to record next (core/plan.h).

#include <optional>
#include <string>
#include <vector>

#include "handeye/core/calibration.h"
#include "handeye/core/plan.h"

namespace handeye {

/// The capture's robot poses (reported T_base_ee), each with the cameras
/// whose views the solve used.
std::vector<PlannedPose> RecordedPoses(const Dataset& dataset, const CalibrationResult& result);

/// The cell as the solved capture knows it: the cameras at their solved
/// poses (± their σ, at least 1 mm and 0.05°) with the intrinsics the solve
/// used, the target's solved pose, the detection noise from the residuals
/// (per axis: the RMS over the cameras' used views / √2) and the robot error
/// the solve modelled. The region and view constraints are `given`'s when
/// given; else the box of the recorded flange positions grown by 0.1 m, with
/// the tool axis within 10° more than the recorded poses' spread about their mean.
PlanCell PlanCellOfResult(const Dataset& dataset, const CalibrationResult& result,
                          const std::optional<PlanCell>& given);

/// What `advise` says.
struct Advice {
  std::map<std::string, PredictedSigma> now;  ///< predicted for the recorded poses
  std::vector<std::string> above_goal;        ///< cameras whose predicted σ exceeds the goal
  CapturePlan next;                           ///< the proposed poses, σ after each
};

/// Proposes `options.poses` poses (fewer when `options.goal_mm` is reached
/// first) after `recorded` that most reduce the worst camera's σ.
Advice Advise(const PlanCell& cell, const std::vector<PlannedPose>& recorded, const PlanOptions& options);

}  // namespace handeye
