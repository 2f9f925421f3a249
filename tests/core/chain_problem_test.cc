// SPDX-License-Identifier: GPL-2.0-or-later
// ChainProblem (core/src/chain_problem.h): the blocks lie in one buffer in
// the order they are added (so Ceres' address orders are the same in every
// process), say what is free and what held, and refuse to outgrow their room.
#include "chain_problem.h"

#include <ceres/problem.h>

#include <catch2/catch.hpp>
#include <stdexcept>

#include "handeye/core/transform.h"
#include "robot_error.h"

using namespace handeye;
using internal::ChainProblem;

namespace {

Eigen::Isometry3d Pose(double x, double angle_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::AngleAxisd(angle_rad, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, -0.2, 1.1);
  return T;
}

}  // namespace

TEST_CASE("ChainProblem: blocks in one buffer, in the order added, at the values given") {
  ChainProblem chain(3, 1);
  double* a = chain.AddPose(Pose(0.1, 0.2));
  double* b = chain.AddPose(Pose(0.4, -0.7), /*constant=*/true);
  std::array<double, OpenCVCameraModel::kNumParams> K{};
  for (int p = 0; p < OpenCVCameraModel::kNumParams; ++p) K[p] = 100.0 + p;
  double* k = chain.AddIntrinsics(K, {0, 1, 2, 3});
  double* c = chain.AddPose(Pose(-0.3, 1.1));
  // One buffer, in the order added: the addresses ascend by the block sizes.
  CHECK(b == a + 7);
  CHECK(k == b + 7);
  CHECK(c == k + OpenCVCameraModel::kNumParams);
  CHECK(ChainProblem::Pose(a).isApprox(Pose(0.1, 0.2), 1e-12));
  CHECK(ChainProblem::Pose(c).isApprox(Pose(-0.3, 1.1), 1e-12));
  for (int p = 0; p < OpenCVCameraModel::kNumParams; ++p) CHECK(k[p] == K[p]);
  // Free and held: poses on the 6-dimensional pose manifold, the held one
  // constant, the intrinsics with only fx, fy, cx, cy free.
  const ceres::Problem& problem = chain.problem();
  CHECK(problem.NumParameterBlocks() == 4);
  CHECK(problem.ParameterBlockTangentSize(a) == 6);
  CHECK_FALSE(problem.IsParameterBlockConstant(a));
  CHECK(problem.IsParameterBlockConstant(b));
  CHECK(problem.ParameterBlockTangentSize(k) == 4);
  // No room left: a fourth pose would move the blocks Ceres holds.
  CHECK_THROWS_AS(chain.AddPose(Pose(0, 0)), std::logic_error);
}

TEST_CASE("ChainProblem: every intrinsic free leaves the block without a subset manifold") {
  ChainProblem chain(0, 1);
  std::vector<int> all(OpenCVCameraModel::kNumParams);
  for (int p = 0; p < OpenCVCameraModel::kNumParams; ++p) all[p] = p;
  double* k = chain.AddIntrinsics({}, all);
  CHECK(chain.problem().ParameterBlockTangentSize(k) == OpenCVCameraModel::kNumParams);
  CHECK(chain.problem().GetManifold(k) == nullptr);
}

TEST_CASE("ChainProblem: a robot pose is a block tied to the reported pose by its prior") {
  ChainProblem chain(1, 0);
  RobotPose reported;
  reported.id = "0001";
  reported.T_base_ee = Pose(0.5, 0.3);
  internal::RobotPrior robot;
  robot.sigma_m = 0.001;
  robot.sigma_rad = 0.0002;
  robot.pixel_sigma_px = 0.5;
  ceres::ResidualBlockId prior = nullptr;
  // eye_to_hand: the robot pose block is T_mount_holder = T_base_ee, started 2 mm off.
  Eigen::Isometry3d start = reported.T_base_ee;
  start.translation().x() += 0.002;
  double* block = chain.AddRobotPose(start, reported, Setup::kEyeToHand, robot, &prior);
  REQUIRE(prior != nullptr);
  CHECK(chain.problem().NumResidualBlocks() == 1);
  double cost = 0;
  chain.problem().EvaluateResidualBlock(prior, false, &cost, nullptr, nullptr);
  // 2 mm at σ 1 mm, weighted by the pixel σ: residual 0.5 · 2 = 1, cost ½ · 1².
  CHECK(cost == Approx(0.5).epsilon(1e-9));
  CHECK(ChainProblem::Pose(block).isApprox(start, 1e-12));
}
