// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Whether the robot's motions can determine the chain at all
// (calibration_problem.cc).

#include <string>
#include <vector>

#include "problem.h"

namespace handeye::internal {

/// Throws SolveError when the used views' robot motions cannot determine T_holder_target
/// (fewer than two motions with non-parallel rotation axes, or tiny rotations).
/// `cameras` limits the check to those cameras (empty: all).
void CheckMotionDiversity(const Problem& problem, const std::vector<int>& cameras = {});
/// The same check for one camera, as a value: empty when fine, else why.
std::string MotionDiversityProblem(const Problem& problem, const std::vector<int>& cameras);

}  // namespace handeye::internal
