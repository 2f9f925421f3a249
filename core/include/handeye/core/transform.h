// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Rigid transforms following SPEC §2: `T_a_b` maps points of frame b into
/// frame a (`p_a = T_a_b * p_b`), so neighbouring indices cancel:
/// `T_base_cam = T_base_ee * T_ee_target * T_target_cam`. Compose with `*`,
/// invert with `.inverse()` (Eigen::Isometry3d). Metres and radians.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string>

namespace handeye {

/// Tolerance on |R^T R - I| (max entry) above which a 4×4 is not rigid.
constexpr double kOrthonormalityTolerance = 1e-6;

/// Largest absolute entry of R^T R - I, or +inf when det(R) < 0 or R has a
/// non-finite entry. 0 for an exact rotation.
double OrthonormalityError(const Eigen::Matrix3d& R);

/// The rotation nearest to M in the Frobenius norm (SVD, det = +1).
Eigen::Matrix3d Orthonormalise(const Eigen::Matrix3d& M);

/// A rigid transform from a homogeneous 4×4 matrix. Returns nullopt and says
/// why in `*why` when an entry is not finite, the last row is not [0 0 0 1],
/// or the rotation is off orthonormal by more than kOrthonormalityTolerance.
/// With `reorthonormalise`, a rotation that is off is replaced by the nearest
/// rotation instead (finite entries, det > 0 and the last row still required).
std::optional<Eigen::Isometry3d> RigidFromMatrix(const Eigen::Matrix4d& M, bool reorthonormalise,
                                                 std::string* why);

/// Rotation vector (axis · angle, radians, angle in [0, π]) of a rotation.
Eigen::Vector3d RotationVectorFromMatrix(const Eigen::Matrix3d& R);
/// Rotation matrix of a rotation vector (axis · angle, radians).
Eigen::Matrix3d MatrixFromRotationVector(const Eigen::Vector3d& rotvec);

/// Angle (radians, in [0, π]) of a rotation, numerically safe near 0 and π.
double RotationAngle(const Eigen::Matrix3d& R);

/// Angle (radians) of R_a^T R_b, the rotation between two orientations.
double RotationDistance(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b);

/// Fixed-axis roll, pitch, yaw (radians) of a rotation: R = Rz(yaw)·Ry(pitch)·Rx(roll),
/// pitch in [-π/2, π/2]. Rebuilding R from the angles is accurate to rounding
/// also at and near pitch = ±π/2, where roll and yaw are not unique. The one
/// form every summary, report and export uses.
Eigen::Vector3d RollPitchYaw(const Eigen::Matrix3d& R);

/// Rigid transform from a rotation (unit quaternion, normalised here) and a translation.
Eigen::Isometry3d MakeTransform(const Eigen::Quaterniond& q, const Eigen::Vector3d& t);
/// Rigid transform from a rotation vector (radians) and a translation.
Eigen::Isometry3d MakeTransformFromRotationVector(const Eigen::Vector3d& rotvec,
                                                  const Eigen::Vector3d& t);

/// Ceres pose parameter block `[qx qy qz qw tx ty tz]` (STYLE.md), quaternion
/// normalised, qw >= 0.
using PoseParams = std::array<double, 7>;
/// The parameter block of a transform (quaternion normalised, qw >= 0).
PoseParams ToPoseParams(const Eigen::Isometry3d& T);
/// The transform of a parameter block `[qx qy qz qw tx ty tz]` (7 doubles).
Eigen::Isometry3d FromPoseParams(const double* params);

/// p_a = T_a_b * p_b with T_a_b given as a `[qx qy qz qw tx ty tz]` block.
/// Usable with Ceres jets. The quaternion must be unit (the manifold keeps it so).
template <typename T>
inline void TransformPoint(const T* T_a_b, const T* p_b, T* p_a) {
  const Eigen::Map<const Eigen::Quaternion<T>> q(T_a_b);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(T_a_b + 4);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p(p_b);
  Eigen::Map<Eigen::Matrix<T, 3, 1>> out(p_a);
  out = q * p + t;
}

}  // namespace handeye
