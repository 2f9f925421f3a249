// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The closed forms (closed_form.cc) and the joint solve's start from them.

#include <map>
#include <optional>
#include <string>
#include <utility>
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

/// Closed-form hand-eye of one camera with a baseline method (tsai … li, visp).
/// Returns (T_cam_mount, T_holder_target) of the camera or nullopt with the reason in *why.
std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> ClosedFormHandEye(
    const Problem& problem, int camera, Method method, std::string* why);

/// One closed-form solution of one camera: the method's name, T_cam_mount, T_holder_target.
struct NamedClosedForm {
  std::string method;
  Eigen::Isometry3d T_cam_mount;
  Eigen::Isometry3d T_holder_target;
};

/// OpenCV's Park and Tsai and ViSP's closed forms on one camera, those that
/// solve: the initialisation candidates of the reprojection solves, which must
/// not print (ViSP's prints are dropped without touching fd 1). Empty with the
/// reason in *why when none solves.
std::vector<NamedClosedForm> SilentClosedForms(const Problem& problem, int camera,
                                               std::string* why);

/// The best (median view RMS of the camera) of SilentClosedForms on one camera.
/// `*chosen` names the method kept; nullopt with the reason in *why when none solves.
std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> SilentClosedFormHandEye(
    const Problem& problem, int camera, std::string* chosen, std::string* why);

/// Linear AX = XB over the motions of all cameras at once (shared T_holder_target), for
/// cameras whose own motions are too few for a per-camera solve.
std::optional<Eigen::Isometry3d> SharedTargetClosedForm(const Problem& problem);

/// The same problem with each camera's used views cut to at most
/// `max_views` chosen for diverse robot rotations (farthest-point sampling):
/// closed forms cost far more than linearly in views, and need diversity, not bulk.
Problem WithDiverseViews(const Problem& problem, size_t max_views);

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
Initialisation InitialiseJoint(const Problem& problem);

}  // namespace handeye::internal
