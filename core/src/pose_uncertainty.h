// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A pose's uncertainty in millimetres and degrees from the covariance of
// its block (uncertainty.cc).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "handeye/core/calibration.h"

namespace handeye::internal {

/// The uncertainty of pose P = T (or T⁻¹ with `invert`) from the
/// tangent-space covariance of the pose block T (PoseManifold).
PoseUncertainty UncertaintyOf(const Eigen::Isometry3d& T,
                              const Eigen::Matrix<double, 6, 6>& tangent_covariance, bool invert);

/// d(position mm, rotation deg of P)/d(tangent of T), P = T or T⁻¹ with
/// `invert` (PoseUncertainty's coordinates: the rotation vector of the error
/// in P's parent frame).
Eigen::Matrix<double, 6, 6> UncertaintyJacobian(const Eigen::Isometry3d& T, bool invert);

}  // namespace handeye::internal
