// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The diagnostics of a solution (diagnostics.cc): the figures and warnings
// that Calibrate() writes into the result and the report only shows.

#include <string>
#include <vector>

#include "problem.h"

namespace handeye::internal {

/// `value` with `decimals` digits after the point, for messages.
std::string Fixed(double value, int decimals);

/// "park" → "Park": a method's name as its authors' in a sentence.
std::string AuthorName(std::string method);

/// Relative robot rotations of more than this many degrees have an axis the
/// diversity checks use; below it the axis is noise-dominated.
constexpr double kMotionAxisMinDeg = 2.0;

/// The robot rotations between every two of the given views (indices into
/// problem.views): their unit axes (rotations above kMotionAxisMinDeg) and
/// the largest angle.
struct RobotMotions {
  std::vector<Eigen::Vector3d> axes;
  double largest_deg = 0;
};
RobotMotions CollectRobotMotions(const Problem& problem, const std::vector<int>& views);

/// The largest angle (degrees) between two of the axes, folded into [0°, 90°];
/// of at most ~1500 of them, evenly spaced, when there are more.
double AxisSpreadDeg(const std::vector<Eigen::Vector3d>& axes);

/// How far apart two poses of one frame in one parent frame are (two
/// T_mount_cam, say): |t_a − t_b| in mm and the angle of R_aᵀ·R_b in degrees.
/// The one measure of a camera pose's error, shared by the closed-form
/// comparison, the ground-truth evaluation (the paper's e_t^GT and e_θ^GT)
/// and the drift check, so that their figures compare.
struct PoseDifference {
  double translation_mm = 0;
  double rotation_deg = 0;
};
PoseDifference DifferenceOf(const Eigen::Isometry3d& T_a, const Eigen::Isometry3d& T_b);

/// The paper's AX = ZB figures of one view (see AxzbError), in metres and radians.
struct AxzbOfView {
  double target_frame_m = 0;
  double camera_frame_m = 0;
  double rotation_rad = 0;
};
/// For the chain T_cam_mount · T_mount_holder · T_holder_target (calibration.h)
/// and the view's PnP pose T_cam_target.
AxzbOfView Axzb(const Eigen::Isometry3d& T_cam_target_pnp, const Eigen::Isometry3d& T_cam_mount,
                const Eigen::Isometry3d& T_mount_holder, const Eigen::Isometry3d& T_holder_target);

/// Camera k of the solution (T_cam_mount, T_holder_target) against the
/// closed form `method` on the camera's own views (on the 150 of most
/// diverse rotation where it has more: OpenCV's closed forms pair every two
/// of them): how far apart the two camera poses are, and by how many pixels
/// the target's points move in the camera's image between them.
ClosedFormComparison CompareWithClosedForm(const Problem& problem, int k,
                                           const Eigen::Isometry3d& T_cam_mount,
                                           const Eigen::Isometry3d& T_holder_target,
                                           Method method);

/// What a disagreement of the solution with the closed form `compared`
/// points at, judged by the other closed forms (closed_form_comparison.cc): the
/// compared closed form that failed, the result's own method that failed,
/// the solve; empty when the closed forms disagree among themselves too.
std::string DisagreementCause(const Problem& problem, int k, const Eigen::Isometry3d& T_cam_mount,
                              const Eigen::Isometry3d& T_holder_target, Method result_method,
                              const ClosedFormComparison& compared, double threshold_px);

/// Per view and per camera residuals, AX = ZB, motion diversity and (with
/// options.compare_closed_form) the closed-form comparison of the solution
/// (T_cam_mount, T_holder_target), written into `result`, whose views (in problem.views order) and
/// cameras exist already; the metrics too. Returns the warnings the
/// thresholds in options.warn call for.
std::vector<Warning> DiagnoseSolution(
    const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target, const CalibrationOptions& options,
    CalibrationResult* result);

}  // namespace handeye::internal
