// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// A calibration result as the static transforms a robot cell publishes, in
/// the formats ROS and OpenCV users paste into their setup (`handeye export`).
///
/// Frames follow ROS REP-103 / REP-105. The calibration estimates the OpenCV
/// camera frame, which REP-103 calls the camera *optical* frame (z forward,
/// x right, y down). ROS drivers also publish a camera *link* (body frame:
/// x forward, y left, z up). For camera `cam0` every format holds
///
///   parent → `cam0_link`                 the calibrated pose, rotated to the body axes
///   `cam0_link` → `cam0_optical_frame`   the fixed rotation OpticalInLink(), no translation
///
/// so that parent → `cam0_optical_frame` is exactly the calibrated T_base_cam
/// (eye_to_hand, parent = the base frame) or T_ee_cam (eye_in_hand, parent =
/// the ee frame: a camera on the robot is static only relative to the flange).
/// ExportOptions::camera_frames renames a camera's optical frame (e.g. to the
/// `camera_color_optical_frame` its driver uses). With
/// ExportOptions::optical_only each camera is one transform, parent →
/// optical frame, and there is no `<camera>_link` (what easy_handeye and
/// MoveIt Calibration publish): for drivers that publish their own body →
/// optical transform, which a second `<camera>_link` parent would contradict.
/// The optical frame then still needs a single parent in the TF tree: the
/// driver's own body → optical transform must not be published too.
/// The target gets ee → target (eye_to_hand) or base → target (eye_in_hand).
/// Lengths in metres, quaternions (x, y, z, w) with w ≥ 0, numbers printed
/// with 17 significant digits (they read back to the same double).
///
/// Formats:
/// - `ros2-launch`: a Python launch file (`*.launch.py`) with one tf2_ros
///   static_transform_publisher node per transform, in the argument style of
///   ROS 2 Humble and later (`--x --y --z --qx --qy --qz --qw --frame-id
///   --child-frame-id`).
/// - `urdf`: fixed joints with `<origin xyz rpy>`, rpy being roll, pitch, yaw
///   about the fixed x, y, z axes (R = Rz(yaw)·Ry(pitch)·Rx(roll), URDF's
///   convention). The file is a valid URDF rooted at the parent frame; the
///   target's joint, whose parent belongs to another branch of the robot's
///   tree, is given in a comment to paste where that link exists.
/// - `tf-static-yaml`: a tf2_msgs/TFMessage in YAML (`transforms:` list of
///   geometry_msgs/TransformStamped), as `ros2 topic echo /tf_static` prints
///   and `ros2 topic pub` accepts.
/// - `opencv-yaml`: cv::FileStorage YAML with 4×4 matrices (`!!opencv-matrix`)
///   per camera: T_<parent>_cam (optical frame, the OpenCV camera frame) and,
///   unless optical_only, T_<parent>_cam_link; plus the target's transform.
///
/// Thread safety: the functions are reentrant (no shared state).

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "handeye/core/calibration.h"
#include "handeye/core/transform.h"  // RollPitchYaw, which the URDF uses

namespace handeye {

/// Output formats of `handeye export` (see the file comment).
enum class ExportFormat { kRos2Launch, kUrdf, kTfStaticYaml, kOpenCvYaml };
/// "ros2-launch", "urdf", "tf-static-yaml", "opencv-yaml".
const char* ExportFormatName(ExportFormat format);
/// Parses a format name; nullopt if unknown.
std::optional<ExportFormat> ParseExportFormat(const std::string& name);
/// Every format name, in the order above.
std::vector<std::string> ExportFormatNames();

/// Frame names of the exported transforms. A frame name is letters, digits
/// and '_', not starting with a digit, optionally with '/' between such parts
/// (a ROS name, so it goes into Python, XML and YAML text with no escaping).
struct ExportOptions {
  std::string base_frame = "base_link";            ///< the robot base (REP-105 base_link)
  std::string ee_frame = "tool0";                  ///< the frame the robot reports (ROS-Industrial tool0)
  std::string target_frame = "calibration_target"; ///< the calibration target
  /// The optical frame's name of a camera (camera name → frame name), for a
  /// camera whose driver names its frames; unlisted cameras get
  /// `<camera>_optical_frame`. Every key must be a camera of the result.
  std::map<std::string, std::string> camera_frames;
  /// One transform per camera, parent → optical frame, and no `<camera>_link`.
  bool optical_only = false;

  /// False, with the reason, when a frame name is not valid or two are equal.
  bool Check(std::string* why) const;
  /// The name given here to a SPEC §2 robot frame, "base" or "ee" (e.g.
  /// SetupFrames::mount): base_frame or ee_frame.
  const std::string& RosName(const std::string& frame) const;
};

/// The pose of a child frame in its parent frame, to publish as a static transform.
struct StaticTransform {
  std::string parent;
  std::string child;
  Eigen::Isometry3d T_parent_child = Eigen::Isometry3d::Identity();
  std::string what;  ///< one line for people, e.g. "cam0 body frame (x forward, y left, z up)"
};

/// R_link_optical as a transform: the optical frame (z forward, x right,
/// y down) in the camera's body frame (x forward, y left, z up), no translation.
/// Its quaternion (x, y, z, w) is (-0.5, 0.5, -0.5, 0.5); rpy (-π/2, 0, -π/2).
Eigen::Isometry3d OpticalInLink();

/// The transforms to publish for `result`, in camera order: for each
/// calibrated camera parent → `<name>_link` and `<name>_link` → its optical
/// frame (parent → optical frame alone with optical_only), then the target's.
/// Cameras that were not calibrated are left out and named in `warnings`
/// (when given). Throws InputError (path `/cameras/<name>`) when a camera name
/// is not a valid frame name or its frames clash with another frame, InputError
/// (path `/cameras`) when camera_frames names a camera the result does not
/// have, and std::invalid_argument when `options` fails Check().
std::vector<StaticTransform> StaticTransformsOf(const CalibrationResult& result, const ExportOptions& options,
                                                std::vector<Warning>* warnings = nullptr);


/// The file content of `result` in `format`. `source` (e.g. the result's
/// path) is named in the file's header comment.
std::string FormatExport(const CalibrationResult& result, ExportFormat format, const ExportOptions& options,
                         const std::string& source, std::vector<Warning>* warnings = nullptr);

/// Writes FormatExport() to `path` atomically. Throws InputError naming the
/// path when it cannot be written.
void ExportResult(const CalibrationResult& result, ExportFormat format, const ExportOptions& options,
                  const std::string& source, const std::string& path, std::vector<Warning>* warnings = nullptr);

}  // namespace handeye
