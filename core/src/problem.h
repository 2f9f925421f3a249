// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The calibration problem as the solver sees it: the robot poses and the
// views (PnP each), the data every stage of the engine reads. What is
// computed from them lives beside it by topic: residuals.h (reprojection
// errors and noise), pose_consensus.h (one side of the chain from the
// other), robot_error.h (the robot's own error), pose_uncertainty.h.

#include <optional>
#include <string>
#include <vector>

#include "handeye/core/calibration.h"

namespace handeye::internal {

/// One observation prepared for the solver.
struct View {
  int camera = 0;
  int pose = 0;
  const Observation* observation = nullptr;
  std::vector<Eigen::Vector3d> p_target;          ///< target points of the detected ids
  std::optional<Eigen::Isometry3d> T_cam_target;  ///< PnP
  double pnp_rms_px = 0;
  bool used = true;
  std::string rejected_because;
  /// Excluded for disagreeing with the other views (robot motion vote or
  /// residuals after a solve), as opposed to failing on its own (PnP).
  bool inconsistent = false;
  /// Excluded for being seen too obliquely (SolvePnp): the angle from
  /// face-on, deg; 0 otherwise.
  double oblique_deg = 0;
  /// Numbered with the target turned half a turn about its normal (ids
  /// reversed on a 180°-ambiguous board): p_target and T_cam_target hold the
  /// turned numbering (FlipView).
  bool flipped = false;
};

/// The dataset in the solver's terms: T_mount_holder per pose and the views.
struct Problem {
  const Dataset* dataset = nullptr;
  std::vector<Eigen::Isometry3d> T_mount_holder;  ///< per pose, SetupFrames::MountFromHolder
  std::vector<View> views;                        ///< every observation
  std::vector<std::vector<int>> camera_views;     ///< used view indices per camera
};

/// Per camera: the T_holder_target its views use (joint: the shared one for every camera).
using TargetPoses = std::vector<Eigen::Isometry3d>;

/// Builds views, runs PnP per view and drops views whose points fit no plane pose.
Problem BuildProblem(const Dataset& dataset, const CalibrationOptions& options);

/// Views seen more obliquely than this are not used. Their corners are
/// squeezed to a quarter and less across the tilt, so their poses are poor
/// (on a rendered METRIC-like cell the views of 75-80 degrees fitted the
/// robot's motions so badly that the consensus called their robot records
/// wrong, and took a good view with them); OpenCV's sector detector found none
/// beyond 74.4 degrees on METRIC or the rendered cells, the lattice of the
/// checkerboard detector finds them up to 80.
constexpr double kMaxViewAngleDeg = 75.0;

/// Angle (rad) between the target's normal and the ray to the middle of the
/// points `p_target`, with the target at `T_cam_target`: 0 seen face-on, π/2
/// edge-on.
double ViewAngle(const Eigen::Isometry3d& T_cam_target,
                 const std::vector<Eigen::Vector3d>& p_target);

/// Rebuilds problem->camera_views from the views' `used` flags.
void IndexUsedViews(Problem* problem);

/// Re-runs PnP of every used view with the problem's (refined) intrinsics.
void RecomputePnp(Problem* problem, double max_rms_px);

}  // namespace handeye::internal
