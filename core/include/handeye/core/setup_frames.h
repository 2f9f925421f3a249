// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The two frames a setup (SPEC §3) fixes things to, named once for both
/// setups, and their names in files and messages.
///
/// - `mount`: the frame the cameras are fixed to (eye_to_hand: base; eye_in_hand: ee);
/// - `holder`: the frame the target is fixed to (eye_to_hand: ee; eye_in_hand: base).
///
/// The solver's chain is then one product whose indices cancel in either setup:
/// T_cam_target[j] = T_cam_mount · T_mount_holder[j] · T_holder_target, where
/// T_mount_holder[j] is the robot's reported T_base_ee[j] or its inverse.
/// CalibrationResult's `T_cam` is T_mount_cam and `T_target` T_holder_target.

#include <Eigen/Geometry>
#include <string>

#include "handeye/core/dataset.h"

namespace handeye {

/// A setup's mount and holder frames in its own (SPEC §2) names.
struct SetupFrames {
  Setup setup = Setup::kEyeToHand;
  std::string mount;   ///< "base" or "ee"
  std::string holder;  ///< "ee" or "base"
  /// The same frames in prose: "base" or "flange".
  std::string mount_in_words;
  std::string holder_in_words;
  /// JSON key and name of T_mount_cam: "T_base_cam" or "T_ee_cam".
  std::string camera_key;
  /// JSON key and name of T_holder_target: "T_ee_target" or "T_base_target".
  std::string target_key;

  /// True when the robot's T_base_ee is T_holder_mount (eye_in_hand), so
  /// T_mount_holder is its inverse.
  bool RobotPoseInverted() const { return setup == Setup::kEyeInHand; }
  /// T_mount_holder of a robot pose given as T_base_ee.
  Eigen::Isometry3d MountFromHolder(const Eigen::Isometry3d& T_base_ee) const;
  /// Where the mount and the holder are in the base frame at robot pose T_base_ee:
  /// T_base_mount (identity or T_base_ee) and T_base_holder (T_base_ee or identity).
  Eigen::Isometry3d BaseFromMount(const Eigen::Isometry3d& T_base_ee) const;
  Eigen::Isometry3d BaseFromHolder(const Eigen::Isometry3d& T_base_ee) const;
};

/// The frames of `setup`: every name that depends on the setup comes from here.
SetupFrames FramesOf(Setup setup);

}  // namespace handeye
