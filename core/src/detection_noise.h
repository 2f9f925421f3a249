// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Cameras that detect the target unlike the others (residuals.cc): the joint
// solve weighs them by their own detection noise, `advise` predicts them
// with it.

#include <vector>

namespace handeye::internal {

struct Problem;

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

/// The median of per-view σ estimates `sigmas`, never below a thousandth of
/// a pixel (DetectionSigmaPx's, over all views).
double MedianSigmaPx(std::vector<double> sigmas);

/// Per group (a camera's views' σ estimates): the median of its own where it
/// differs from all groups' together by more than three standard errors of
/// the difference (from the spread of the estimates), else 0; 0 also for a
/// group of fewer than 3.
std::vector<double> SigmasApart(const std::vector<std::vector<double>>& sigmas);

}  // namespace handeye::internal
