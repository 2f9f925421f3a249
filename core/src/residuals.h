// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Reprojection residuals of views through a solution, and the noise they
// and the PnP fits show (residuals.cc; each camera's own: detection_noise.h).

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

}  // namespace handeye::internal
