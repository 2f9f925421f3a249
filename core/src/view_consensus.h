// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Which views to trust: the robot-motion vote, the views off a solution and
// the robot records that disagree (view_consensus.cc).

#include <string>
#include <vector>

#include "problem.h"

namespace handeye::internal {

/// The robot-motion vote, before any estimate: for two views a, b of one
/// camera, the target's motion seen by the camera (T_cam_target[a] ·
/// T_cam_target[b]⁻¹) and the robot's motion (M_a · M_b⁻¹) are conjugate
/// (T_cam_mount between them), so their rotation angles and screw pitches agree
/// whatever T_cam_mount and T_holder_target are, within what PnP's noise
/// allows each pair. A view that agrees with fewer than half of the
/// camera's other views, where most views agree with most, is excluded: its
/// robot record belongs to another pose, or its image to another time (or,
/// seen very obliquely, its pose is worse than its corners' noise says).
/// On a 180°-ambiguous target the views are first numbered alike
/// (NumberViewsAlike), and a view that still disagrees is numbered the other
/// way round (FlipView): when that agrees with half of the others, it is used so.
/// Returns the number of views excluded.
int RejectInconsistentMotions(Problem* problem);

/// Used views whose RMS through the solution lies far outside the robust
/// distribution of view RMS (per camera where it has five views or more):
/// above max(median + 8·1.4826·MAD, 4·median, 0.5 px).
std::vector<int> ViewsOffTheSolution(
    const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target);

/// Views excluded as inconsistent that fit the solution with the target turned
/// over (a half turn about an axis in its plane) are a see-through target read
/// from behind, whose mirrored pattern PnP takes for a front view: says so.
void ExplainInconsistentViews(Problem* problem,
                              const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                              const TargetPoses& T_holder_target);

/// One warning per robot pose all of whose views were excluded as
/// inconsistent: the pose record and the images likely do not belong together.
std::vector<Warning> PoseRecordWarnings(
    const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target);

}  // namespace handeye::internal
