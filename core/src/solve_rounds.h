// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The rounds around the nonlinear solve and the leave-one-pose-out check
// (solve_rounds.cc).

#include <functional>
#include <optional>
#include <vector>

#include "initialisation.h"
#include "problem.h"
#include "refinement.h"
#include "robot_error.h"

namespace handeye::internal {

/// Per camera, the T_holder_target its views use (one shared, or one per camera).
TargetPoses TargetPosesOf(const Refinement& refined, size_t num_cameras);

/// The nonlinear solve made robust: `solve(scale)` runs one refinement
/// (warm-started by the caller from the last one). After each solve, views far
/// outside the robust residual distribution are excluded and the loss scale is
/// set from the residuals (when not fixed), then it solves again, until
/// nothing changes (at most a few rounds). Warnings go to *warnings.
Refinement RobustSolve(Problem* problem, const CalibrationOptions& options, double first_scale,
                       const std::function<Refinement(double scale_px)>& solve,
                       std::vector<Warning>* warnings);

/// Leave-one-pose-out: for each robot pose with used views, the joint solve
/// without them (from `init`, the solution), its prediction of their points,
/// and how far each camera moved from the full solve. One entry per camera.
void CrossValidate(const Problem& problem, const Initialisation& init,
                   const CalibrationOptions& options, const std::optional<RobotPrior>& robot,
                   std::vector<CameraResult::CrossValidation>* out);

/// The views of a fold's robot poses predicted by the joint solve without
/// them: squared pixel errors summed over their points, each camera's
/// weighed as the solve weighs it (CameraWeights), and the count.
struct FoldError {
  bool solved = false;
  double sum_sq_px = 0;
  int points = 0;
};

/// k-fold over the robot poses that have used views (pose i of them in fold
/// i mod `folds`): for each fold, the joint solve (from `init`, under `robot`)
/// without the fold's views, and its prediction of them through the reported
/// robot poses, with the intrinsics that solve refined.
std::vector<FoldError> HeldOutErrors(const Problem& problem, const Initialisation& init,
                                     const CalibrationOptions& options,
                                     const std::optional<RobotPrior>& robot, int folds);

}  // namespace handeye::internal
