// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Where the joint solve starts (closed_form.cc makes it, the refinements
// read it).

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "handeye/core/calibration.h"

namespace handeye::internal {

/// Initial T_cam_mount (per camera, nullopt for cameras without views) and
/// T_holder_target for the joint solve.
struct Initialisation {
  std::vector<std::optional<Eigen::Isometry3d>> T_cam_mount;
  Eigen::Isometry3d T_holder_target = Eigen::Isometry3d::Identity();
  std::vector<std::string> notes;
  /// Per camera, the intrinsics (OpenCVCameraModel indices) that are unknowns
  /// of the joint solve, started from the problem's cameras; empty: fixed.
  std::vector<std::vector<int>> free_intrinsics;
  /// The given intrinsics (the prior's centre, see IntrinsicsPrior) and the
  /// pixel σ that weighs the prior against the reprojection residuals.
  std::vector<Camera> given_cameras;
  double pixel_sigma_px = 1.0;
  /// Per camera: its T_cam_mount is held at its start (CalibrationOptions::fixed_cameras).
  std::vector<bool> fixed_T_cam_mount;
  /// With a robot prior: per pose, the start of its block (empty: the reported pose).
  std::vector<std::optional<Eigen::Isometry3d>> T_mount_holder;
  /// Per ordered camera pair (k, t) of the cross terms: the start of
  /// T_camk_camt (absent: T_camk_mount · T_mount_camt, the cameras' own).
  std::map<std::pair<int, int>, Eigen::Isometry3d> T_camk_camt;
};

}  // namespace handeye::internal
