// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The closed forms (closed_form.cc) and the joint solve's start from them.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "initialisation.h"
#include "problem.h"

namespace handeye::internal {

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

/// Which closed forms SilentClosedForms runs: OpenCV's Park and Tsai and
/// ViSP's, or only OpenCV's two. ViSP's is silenced under a process-wide lock,
/// so calls on several threads wait for each other, and its virtual visual
/// servoing costs several times the other two.
enum class ClosedForms { kWithVisp, kOpenCvOnly };

/// The closed forms `which` of one camera, those that solve: the
/// initialisation candidates of the reprojection solves, which must not print
/// (ViSP's prints are dropped without touching fd 1). Empty with the reason in
/// *why when none solves.
std::vector<NamedClosedForm> SilentClosedForms(const Problem& problem, int camera, std::string* why,
                                               ClosedForms which = ClosedForms::kWithVisp);

/// The best (median view RMS of the camera) of SilentClosedForms on one camera.
/// `*chosen` names the method kept; nullopt with the reason in *why when none solves.
std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> SilentClosedFormHandEye(
    const Problem& problem, int camera, std::string* chosen, std::string* why,
    ClosedForms which = ClosedForms::kWithVisp);

/// Linear AX = XB over the motions of all cameras at once (shared T_holder_target), for
/// cameras whose own motions are too few for a per-camera solve.
std::optional<Eigen::Isometry3d> SharedTargetClosedForm(const Problem& problem);

/// The same problem with each camera's used views cut to at most
/// `max_views` chosen for diverse robot rotations (farthest-point sampling):
/// closed forms cost far more than linearly in views, and need diversity, not bulk.
Problem WithDiverseViews(const Problem& problem, size_t max_views);

/// The joint solve's start from the closed forms of every camera.
Initialisation InitialiseJoint(const Problem& problem);

}  // namespace handeye::internal
