// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Which views to trust: the robot-motion vote, the half-turn numbering of
// ambiguous boards, the views off a solution and the robot records that
// disagree (view_consensus.cc, half_turn.cc, diagnostics).

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

/// The half turn F of a 180°-ambiguous target (a checkerboard with
/// cols + rows even) about its normal through its centre, which takes point
/// id to point N − 1 − id; nullopt for a target that has none.
std::optional<Eigen::Isometry3d> HalfTurnSymmetry(const Target& target);

/// Numbers `view` the other way round by the half turn F (HalfTurnSymmetry):
/// every p_target becomes F · p_target (its id's partner, N − 1 − id) and
/// T_cam_target becomes T_cam_target · F, so the pixels and the pose stay as
/// seen; `flipped` toggles.
void FlipView(const Eigen::Isometry3d& F, View* view);

/// Numbers every used view of a 180°-ambiguous target alike, by the half
/// turn F (HalfTurnSymmetry): within a camera, each pair of views is numbered
/// alike when their target motion's rotation angle matches the robot's, and
/// the other way round when it matches only with one of them turned (FlipView);
/// the numbering that most pairs agree with is taken. Between cameras, the
/// one under which the views of the poses two cameras share give one
/// camera-to-camera transform. Of the two numberings of the whole set, the
/// one that turns fewer views. Returns the number of views flipped.
int NumberViewsAlike(Problem* problem, const Eigen::Isometry3d& F);

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

/// Throws SolveError when the used views' robot motions cannot determine T_holder_target
/// (fewer than two motions with non-parallel rotation axes, or tiny rotations).
/// `cameras` limits the check to those cameras (empty: all).
void CheckMotionDiversity(const Problem& problem, const std::vector<int>& cameras = {});
/// The same check for one camera, as a value: empty when fine, else why.
std::string MotionDiversityProblem(const Problem& problem, const std::vector<int>& cameras);

}  // namespace handeye::internal
