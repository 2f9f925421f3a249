// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// One side of the chain from the other through the views' PnP poses, and
// the mean of pose estimates (calibration_problem.cc).

#include <optional>
#include <vector>

#include "problem.h"

namespace handeye::internal {

/// Camera k's T_cam_mount given T_holder_target, from its PnP views (consensus of
/// T_cam_target · T_target_holder · T_holder_mount[j]).
/// (Not a T_cam_target: sim's TrueCameraFromTarget is that.)
std::optional<Eigen::Isometry3d> CameraGivenTarget(const Problem& problem, int camera,
                                                   const Eigen::Isometry3d& T_holder_target);
/// T_holder_target given camera k's T_cam_mount, from its PnP views (consensus of
/// T_holder_mount[j] · T_mount_cam · T_cam_target).
std::optional<Eigen::Isometry3d> TargetGivenCamera(const Problem& problem, int camera,
                                                   const Eigen::Isometry3d& T_cam_mount);

/// Chordal L2 mean of rotations and mean of translations.
Eigen::Isometry3d MeanTransform(const std::vector<Eigen::Isometry3d>& transforms);

}  // namespace handeye::internal
