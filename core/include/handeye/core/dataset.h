// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// In-memory form of the dataset, observation and ground-truth files
/// (SPEC §4, §5). io/ reads and writes them; the solver only sees these types.

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "handeye/core/camera.h"
#include "handeye/core/target.h"

namespace handeye {

/// SPEC §3.
enum class Setup { kEyeToHand, kEyeInHand };
/// "eye_to_hand" / "eye_in_hand".
const char* SetupName(Setup setup);
/// Parses a setup name; nullopt if unknown.
std::optional<Setup> ParseSetup(const std::string& name);

/// One robot pose: what the controller reported, and the images taken there.
struct RobotPose {
  std::string id;  ///< unique within the dataset (SPEC §4 `poses[].id`)
  /// Pose of the ee frame (flange or TCP, whatever the robot reports) in the
  /// robot base frame; metres.
  Eigen::Isometry3d T_base_ee = Eigen::Isometry3d::Identity();
  /// camera name → image path (absolute, or relative to the working directory;
  /// the loader resolves paths relative to the dataset file).
  std::map<std::string, std::string> images;
};

/// The target points one camera detected in the image of one pose.
struct Observation {
  std::string pose_id;  ///< RobotPose::id of the pose the image was taken at
  std::string camera;   ///< Camera::name
  std::vector<int> ids;                    ///< ids of Target::Points(), unique
  std::vector<Eigen::Vector2d> points_px;  ///< same length as ids
};

/// A calibration problem: everything of a dataset, plus the observations once
/// detected (empty for a dataset that has only images). A plain value: copy
/// it freely (the target is shared, immutable and thread-safe); concurrent
/// reads are safe, a writer needs exclusive access.
struct Dataset {
  Setup setup = Setup::kEyeToHand;
  /// The calibration target (MakeTarget, handeye/detectors/registry.h).
  std::shared_ptr<const Target> target;
  std::vector<Camera> cameras;  ///< names unique
  std::vector<RobotPose> poses;  ///< ids unique
  /// Detected target points per view; what Calibrate() uses.
  std::vector<Observation> observations;

  /// Index of the camera with this name, or -1.
  int CameraIndex(const std::string& name) const;
  /// Index of the pose with this id, or -1.
  int PoseIndex(const std::string& id) const;
};

/// Ground truth of a (simulated) dataset, SPEC §4.
struct GroundTruth {
  Setup setup = Setup::kEyeToHand;
  /// eye_to_hand: T_base_cam per camera; eye_in_hand: T_ee_cam per camera.
  std::map<std::string, Eigen::Isometry3d> T_cam;
  /// eye_to_hand: T_ee_target; eye_in_hand: T_base_target.
  Eigen::Isometry3d T_target = Eigen::Isometry3d::Identity();
  /// False when the truth does not include T_target (e.g. METRIC's GT/ gives
  /// camera poses only): T_target is then meaningless and is not written.
  bool has_T_target = true;

  /// Per pose (simulator only): the true robot pose and true pixel positions.
  struct PoseTruth {
    std::string id;
    Eigen::Isometry3d T_base_ee_true = Eigen::Isometry3d::Identity();
    std::map<std::string, Observation> points_px;  ///< camera name → true points
  };
  std::vector<PoseTruth> poses;
};

}  // namespace handeye
