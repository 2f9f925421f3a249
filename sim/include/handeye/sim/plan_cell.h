// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The planning view of a simulated cell (core/plan.h): what a user would
/// know before a capture — the intrinsics, camera and target poses off the
/// truth by a tape measure's error — and the simulator's reachable region.

#include <cstdint>

#include "handeye/core/plan.h"
#include "handeye/sim/synthetic.h"

namespace handeye {

/// How well the cell is known before the capture.
struct RoughKnowledge {
  double position_mm = 20;   ///< ± of each camera's and the target's position
  double rotation_deg = 1;   ///< ± of their orientation
  std::uint64_t seed = 1;    ///< the error actually drawn (1σ of the ± per axis)
  double robot_sigma_mm = 0.3, robot_sigma_deg = 0.03;
  double pixel_sigma_px = 0.2;
};

/// A PlanCell for `scene`: its cameras with their intrinsics, their true
/// poses and the target's moved by a random error of the given ±, and as
/// the region the box the simulator's flange positions lie in (eye_to_hand:
/// around the base, eye_in_hand: in front of the fixed target).
PlanCell PlanCellOfScene(const SyntheticScene& scene, const RoughKnowledge& rough);

}  // namespace handeye
