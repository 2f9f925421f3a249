// SPDX-License-Identifier: GPL-2.0-or-later
#include <catch2/catch.hpp>

#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"

using namespace handeye;

TEST_CASE("Setup frames name the mount and the holder in the setup's own names", "[setup_frames]") {
  struct Expected {
    Setup setup;
    const char *mount, *holder, *mount_in_words, *holder_in_words, *camera_key, *target_key;
    bool robot_pose_inverted;
  };
  for (const Expected& e : {Expected{Setup::kEyeToHand, "base", "ee", "base", "flange", "T_base_cam", "T_ee_target", false},
                            Expected{Setup::kEyeInHand, "ee", "base", "flange", "base", "T_ee_cam", "T_base_target", true}}) {
    INFO(SetupName(e.setup));
    const SetupFrames frames = FramesOf(e.setup);
    CHECK(frames.setup == e.setup);
    CHECK(frames.mount == e.mount);
    CHECK(frames.holder == e.holder);
    CHECK(frames.mount_in_words == e.mount_in_words);
    CHECK(frames.holder_in_words == e.holder_in_words);
    CHECK(frames.camera_key == e.camera_key);
    CHECK(frames.target_key == e.target_key);
    CHECK(frames.RobotPoseInverted() == e.robot_pose_inverted);
  }
}

TEST_CASE("Setup frames' robot poses make the chain cancel in the base frame", "[setup_frames]") {
  const Eigen::Isometry3d T_base_ee = MakeTransformFromRotationVector({0.3, -0.2, 0.9}, {0.4, -0.1, 0.6});
  const Eigen::Isometry3d T_mount_cam = MakeTransformFromRotationVector({-1.2, 0.1, 0.4}, {0.05, 0.7, 1.1});
  const Eigen::Isometry3d T_holder_target = MakeTransformFromRotationVector({0.2, 2.0, -0.3}, {0.0, 0.02, 0.15});
  for (const Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    INFO(SetupName(setup));
    const SetupFrames frames = FramesOf(setup);
    // The mount's and the holder's poses in the base: one of them is the base itself.
    const Eigen::Isometry3d T_base_mount = frames.BaseFromMount(T_base_ee);
    const Eigen::Isometry3d T_base_holder = frames.BaseFromHolder(T_base_ee);
    CHECK((T_base_mount.isApprox(Eigen::Isometry3d::Identity()) != T_base_holder.isApprox(Eigen::Isometry3d::Identity())));
    CHECK(frames.MountFromHolder(T_base_ee).isApprox(T_base_mount.inverse() * T_base_holder, 1e-12));
    // The solver's chain equals the target seen through the base frame.
    const Eigen::Isometry3d T_cam_target_chain =
        T_mount_cam.inverse() * frames.MountFromHolder(T_base_ee) * T_holder_target;
    const Eigen::Isometry3d T_cam_target_base =
        (T_base_mount * T_mount_cam).inverse() * (T_base_holder * T_holder_target);
    CHECK(T_cam_target_chain.isApprox(T_cam_target_base, 1e-12));
  }
  CHECK(FramesOf(Setup::kEyeToHand).MountFromHolder(T_base_ee).isApprox(T_base_ee, 1e-15));
  CHECK(FramesOf(Setup::kEyeInHand).MountFromHolder(T_base_ee).isApprox(T_base_ee.inverse(), 1e-15));
}
