// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/setup_frames.h"

namespace handeye {

SetupFrames FramesOf(Setup setup) {
  SetupFrames frames;
  frames.setup = setup;
  const bool cameras_on_base = setup == Setup::kEyeToHand;
  frames.mount = cameras_on_base ? "base" : "ee";
  frames.holder = cameras_on_base ? "ee" : "base";
  frames.mount_in_words = cameras_on_base ? "base" : "flange";
  frames.holder_in_words = cameras_on_base ? "flange" : "base";
  frames.camera_key = "T_" + frames.mount + "_cam";
  frames.target_key = "T_" + frames.holder + "_target";
  return frames;
}

Eigen::Isometry3d SetupFrames::MountFromHolder(const Eigen::Isometry3d& T_base_ee) const {
  return RobotPoseInverted() ? T_base_ee.inverse() : T_base_ee;
}

Eigen::Isometry3d SetupFrames::BaseFromMount(const Eigen::Isometry3d& T_base_ee) const {
  return mount == "base" ? Eigen::Isometry3d::Identity() : T_base_ee;
}

Eigen::Isometry3d SetupFrames::BaseFromHolder(const Eigen::Isometry3d& T_base_ee) const {
  return holder == "base" ? Eigen::Isometry3d::Identity() : T_base_ee;
}

}  // namespace handeye
