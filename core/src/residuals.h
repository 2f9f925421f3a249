// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Reprojection residuals of views through a solution, and the noise they
// and the PnP fits show (residuals.cc).

#include <optional>
#include <vector>

#include "problem.h"

namespace handeye::internal {

/// The median of `values` (the upper of the two middle ones for an even
/// count); 0 for none.
double Median(std::vector<double> values);

/// Reprojection errors (pixels) of one view's points through
/// T_cam_mount · T_mount_holder[j] · T_holder_target.
std::vector<double> ViewErrors(const Problem& problem, const View& view,
                               const Eigen::Isometry3d& T_cam_mount,
                               const Eigen::Isometry3d& T_holder_target);

/// RMS of a view's point errors (pixels), and the largest in *max_error (may be null).
double ViewRms(const std::vector<double>& errors, double* max_error = nullptr);

/// Median over used views of the per-view RMS reprojection error for (T_cam_mount,
/// T_holder_target).
double MedianViewRms(const Problem& problem,
                     const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                     const Eigen::Isometry3d& T_holder_target);

/// σ (pixels, per image axis) of the reprojection residuals of the used
/// views, from their median (robust to a few bad points).
double ResidualSigmaPx(const Problem& problem,
                       const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                       const TargetPoses& T_holder_target);

/// Detection noise σ per image axis (pixels): the median over used views of
/// what their PnP fit leaves (2n − 6 degrees of freedom for n points).
double DetectionSigmaPx(const Problem& problem);

/// Per camera, its own detection noise σ (DetectionSigmaPx over that
/// camera's used views) where it differs from all views' by more than three
/// standard errors of the difference (from the spread of the views' σ), else
/// DetectionSigmaPx's: cameras that detect alike are weighed alike, and a
/// blurred, distant or low-resolution camera that detects the target several
/// times worse than the others gets its own.
std::vector<double> CameraSigmasPx(const Problem& problem);

/// Per camera, the weight of its pixel residuals in the joint solve and in
/// the held-out poses' errors: DetectionSigmaPx over its CameraSigmasPx, so
/// that a camera that detects worse weighs less in the shared target
/// transform, and every weighed residual has the σ the robot's and the
/// intrinsics' priors are weighed against. Weighed alike, one camera of four
/// at 0.7 px among cameras at 0.03 px (rendered cells of bench/robot-model,
/// noise added to its corners, 6 seeds) put the others 3-5x further from the
/// truth (exact robot 0.101 against 0.034 mm, robot 0.5 mm / 0.05° 2.56
/// against 0.49 mm) and gave them 8x the σ (2.26 against 0.28 mm).
std::vector<double> CameraWeights(const Problem& problem);

}  // namespace handeye::internal
