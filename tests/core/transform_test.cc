// SPDX-License-Identifier: GPL-2.0-or-later
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <random>

#include "handeye/core/transform.h"

using namespace handeye;

namespace {

Eigen::Matrix3d FromRpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace

TEST_CASE("Rotation vector round trip, including angles near pi", "[transform]") {
  for (double angle : {0.0, 1e-9, 0.3, 2.0, M_PI - 1e-7, M_PI}) {
    const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
    const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    const Eigen::Vector3d rv = RotationVectorFromMatrix(R);
    CHECK((MatrixFromRotationVector(rv) - R).norm() < 1e-12);
    CHECK(std::abs(RotationAngle(R) - angle) < 1e-9);
  }
}

TEST_CASE("Neighbouring indices cancel", "[transform]") {
  const Eigen::Isometry3d T_base_ee = MakeTransformFromRotationVector({0.1, 0.2, -0.3}, {0.4, 0.1, 0.9});
  const Eigen::Isometry3d T_ee_target = MakeTransformFromRotationVector({-0.5, 0.1, 0.0}, {0.0, 0.0, 0.1});
  const Eigen::Vector3d p_target(0.05, 0.1, 0.0);
  const Eigen::Isometry3d T_base_target = T_base_ee * T_ee_target;
  CHECK((T_base_target * p_target - T_base_ee * (T_ee_target * p_target)).norm() < 1e-15);
  CHECK(((T_base_target.inverse() * T_base_target).matrix() - Eigen::Matrix4d::Identity()).norm() < 1e-15);
}

TEST_CASE("Pose parameter block round trip and TransformPoint", "[transform]") {
  const Eigen::Isometry3d T = MakeTransformFromRotationVector({2.5, -0.7, 0.4}, {1, 2, 3});
  const PoseParams p = ToPoseParams(T);
  CHECK(p[3] >= 0);
  CHECK((FromPoseParams(p.data()).matrix() - T.matrix()).norm() < 1e-14);
  const Eigen::Vector3d x(0.3, -0.2, 1.1);
  Eigen::Vector3d y;
  TransformPoint(p.data(), x.data(), y.data());
  CHECK((y - T * x).norm() < 1e-14);
}

TEST_CASE("RigidFromMatrix checks orthonormality", "[transform]") {
  Eigen::Matrix4d M = MakeTransformFromRotationVector({0.1, 0.2, 0.3}, {1, 2, 3}).matrix();
  std::string why;
  REQUIRE(RigidFromMatrix(M, false, &why));
  Eigen::Matrix4d off = M;
  off(0, 0) += 1e-3;
  CHECK_FALSE(RigidFromMatrix(off, false, &why));
  CHECK(why.find("orthonormal") != std::string::npos);
  const auto fixed = RigidFromMatrix(off, true, &why);
  REQUIRE(fixed);
  CHECK(OrthonormalityError(fixed->rotation()) < 1e-12);
  CHECK((fixed->rotation() - M.topLeftCorner<3, 3>()).norm() < 2e-3);
  Eigen::Matrix4d nan = M;
  nan(1, 3) = std::nan("");
  CHECK_FALSE(RigidFromMatrix(nan, true, &why));
  Eigen::Matrix4d mirror = M;
  mirror.col(0) *= -1;
  CHECK_FALSE(RigidFromMatrix(mirror, true, &why));
  Eigen::Matrix4d bottom = M;
  bottom(3, 0) = 0.1;
  CHECK_FALSE(RigidFromMatrix(bottom, false, &why));
}

TEST_CASE("Roll, pitch, yaw rebuild the rotation, also at and near gimbal lock", "[transform]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  double worst = 0;
  auto check = [&](const Eigen::Matrix3d& R) {
    const Eigen::Vector3d rpy = RollPitchYaw(R);
    CHECK(std::abs(rpy.y()) <= M_PI / 2);
    worst = std::max(worst, (FromRpy(rpy.x(), rpy.y(), rpy.z()) - R).cwiseAbs().maxCoeff());
  };
  for (int i = 0; i < 1000; ++i) check(FromRpy(angle(rng), angle(rng) / 2, angle(rng)));
  for (double pitch : {M_PI / 2, -M_PI / 2})
    for (double off : {0.0, 1e-4, 1e-7, 1e-9, 1e-12, 1e-15})
      for (int i = 0; i < 20; ++i) check(FromRpy(angle(rng), pitch - (pitch > 0 ? off : -off), angle(rng)));
  // A few units of rounding; the parse-back tests need 1e-9.
  CHECK(worst < 5e-15);
}
