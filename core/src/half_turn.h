// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Boards that look the same turned half a turn about their normal, and
// their views numbered alike (half_turn.cc).

#include <optional>

#include "handeye/core/target.h"
#include "problem.h"

namespace handeye::internal {

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

}  // namespace handeye::internal
