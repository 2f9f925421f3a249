// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// What the cell writer (cell_json.cc) and the plan writer (plan_json.cc) share.

#include <nlohmann/json.hpp>

#include "handeye/core/plan.h"

namespace handeye::internal {

/// A cell's `noise` object: detection σ, the robot's error σ and how far
/// off the given intrinsics may be.
nlohmann::ordered_json NoiseJson(const PlanCell& cell);

}  // namespace handeye::internal
