// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Cramér–Rao bound of the calibration: the covariance of the estimated
/// camera positions implied by isotropic pixel noise, from the Jacobian of
/// the reprojection model (each detected point counted once) at given values.

#include <Eigen/Core>
#include <map>
#include <string>

#include "handeye/core/calibration.h"

namespace handeye {

/// Cramér–Rao covariance of every camera's pose, by camera name.
struct PositionCovariance {
  /// Camera name → 3×3 covariance (m²) of the camera position: t of T_base_cam
  /// (eye_to_hand) or of T_ee_cam (eye_in_hand).
  std::map<std::string, Eigen::Matrix3d> camera_position;
  /// Camera name → 3×3 covariance (rad²) of the camera orientation (tangent space).
  std::map<std::string, Eigen::Matrix3d> camera_rotation;
};

/// Covariance at the transforms in `at` (e.g. the ground truth, or a result)
/// for pixel noise σ `noise_px`, for the shared-target model (one T_holder_target). Uses every point of
/// every observation of the dataset. Throws SolveError when the information
/// matrix is singular (the problem is not observable).
PositionCovariance ComputePositionCovariance(const Dataset& dataset, const CalibrationResult& at,
                                             double noise_px);

}  // namespace handeye
