// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/transform.h"

#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace handeye {

double OrthonormalityError(const Eigen::Matrix3d& R) {
  if (!R.allFinite() || R.determinant() <= 0.0) return std::numeric_limits<double>::infinity();
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
}

Eigen::Matrix3d Orthonormalise(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

std::optional<Eigen::Isometry3d> RigidFromMatrix(const Eigen::Matrix4d& M, bool reorthonormalise,
                                                 std::string* why) {
  auto fail = [why](const std::string& reason) -> std::optional<Eigen::Isometry3d> {
    if (why) *why = reason;
    return std::nullopt;
  };
  if (!M.allFinite()) return fail("a rigid 4x4 transform with finite entries (found NaN or Inf)");
  if (M.row(3).transpose() != Eigen::Vector4d(0, 0, 0, 1))
    return fail("a rigid 4x4 transform whose last row is [0, 0, 0, 1]");
  Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if (R.determinant() <= 0.0)
    return fail("a rigid 4x4 transform (the rotation part has determinant <= 0: a reflection "
                "or a singular matrix)");
  const double err = OrthonormalityError(R);
  if (err > kOrthonormalityTolerance) {
    if (!reorthonormalise) {
      char off[32];
      std::snprintf(off, sizeof off, "%.2g", err);
      return fail("a rigid 4x4 transform (the rotation part is off orthonormal by " +
                  std::string(off) +
                  ", more than 1e-6: rounded when it was printed? --reorthonormalise replaces it "
                  "by the nearest "
                  "rotation)");
    }
    R = Orthonormalise(R);
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = M.topRightCorner<3, 1>();
  return T;
}

double RotationAngle(const Eigen::Matrix3d& R) {
  // atan2 of |sin| and cos stays accurate near 0 and π, where acos alone does not.
  const Eigen::Vector3d axis_sin(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  return std::atan2(0.5 * axis_sin.norm(), 0.5 * (R.trace() - 1.0));
}

double RotationDistance(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b) {
  return RotationAngle(R_a.transpose() * R_b);
}

Eigen::Vector3d RollPitchYaw(const Eigen::Matrix3d& R) {
  // atan2 forms throughout: asin(-R20) would lose half the digits near ±90°.
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  const double pitch = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0)));
  // Roll from what is left once yaw and pitch are undone; near pitch = ±90°
  // the yaw above is poorly determined and this roll absorbs its error, so
  // the three angles still rebuild R to rounding.
  const Eigen::Matrix3d rest = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix()
                                   .transpose() *
                               R;
  const double roll = std::atan2(rest(2, 1), rest(1, 1));
  return Eigen::Vector3d(roll, pitch, yaw);
}

Eigen::Vector3d RotationVectorFromMatrix(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(Eigen::Quaterniond(R).normalized());
  double angle = aa.angle();
  Eigen::Vector3d axis = aa.axis();
  if (angle > M_PI) {
    angle = 2.0 * M_PI - angle;
    axis = -axis;
  }
  return axis * angle;
}

Eigen::Matrix3d MatrixFromRotationVector(const Eigen::Vector3d& rotvec) {
  const double angle = rotvec.norm();
  if (angle < 1e-300) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, rotvec / angle).toRotationMatrix();
}

Eigen::Isometry3d MakeTransform(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = t;
  return T;
}

Eigen::Isometry3d MakeTransformFromRotationVector(const Eigen::Vector3d& rotvec,
                                                  const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = MatrixFromRotationVector(rotvec);
  T.translation() = t;
  return T;
}

PoseParams ToPoseParams(const Eigen::Isometry3d& T) {
  Eigen::Quaterniond q(T.rotation());
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Eigen::Vector3d t = T.translation();
  return {q.x(), q.y(), q.z(), q.w(), t.x(), t.y(), t.z()};
}

Eigen::Isometry3d FromPoseParams(const double* params) {
  const Eigen::Quaterniond q(params[3], params[0], params[1], params[2]);
  return MakeTransform(q, Eigen::Vector3d(params[4], params[5], params[6]));
}

}  // namespace handeye
