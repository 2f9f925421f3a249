// SPDX-License-Identifier: GPL-2.0-or-later
// SolutionCovariance (core/src/refine_covariance.cc, refine_internal.h) on a
// problem linear in its parameters with the joint solve's blocks: a camera's
// T_cam_mount, T_holder_target, intrinsics with held parameters, and robot
// pose blocks under a prior. Where the robot's settled σ differs from the
// prior's, its block-wise sandwich must be the dense A⁻¹ B A⁻¹, B the
// information with the prior rows reweighted by (settled / prior σ)².
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "consider_covariance.h"
#include "covariance.h"
#include "pose_manifold.h"
#include "refine_internal.h"
#include "refinement.h"
#include "robot_error.h"
#include "support/linear_problem.h"

using handeye::OpenCVCameraModel;
using handeye::internal::ConsiderCovariance;
using handeye::internal::PoseManifold;
using handeye::internal::RobotPoseBlock;
using handeye::internal::RobotPrior;
using handeye::test::LinearProblem;
using handeye::test::RandomMatrix;

namespace {

constexpr int kN = OpenCVCameraModel::kNumParams;
constexpr int kRobotPoses = 3;

std::vector<double> PoseAt(double angle_rad, double x) {
  const Eigen::Quaterniond q(
      Eigen::AngleAxisd(angle_rad, Eigen::Vector3d(0.2, 1.0, -0.4).normalized()));
  return {q.x(), q.y(), q.z(), q.w(), x, 0.1, 0.9};
}

/// The blocks of a joint solve, each view seeing all of them linearly: 8
/// residuals per view, two views per robot pose; intrinsics fx, fy, cx, cy
/// free. `singular`: the views do not see cy (a zero column). `prior`: cx
/// and cy under a prior L (K₂,₃ − given) of information P = LᵀL.
struct JointCell {
  explicit JointCell(bool singular, bool prior = false) {
    std::mt19937_64 rng(41);
    cam = linear.AddBlock(PoseAt(0.4, 0.3), [] { return new PoseManifold; });
    target = linear.AddBlock(PoseAt(-1.1, -0.2), [] { return new PoseManifold; });
    std::vector<double> K(kN, 0.01);
    K[0] = K[1] = 600.0;
    K[2] = 320.0;
    K[3] = 240.0;
    std::vector<int> held;
    for (int p = 4; p < kN; ++p) held.push_back(p);
    intrinsics = linear.AddBlock(K, [held] { return new ceres::SubsetManifold(kN, held); });
    for (int j = 0; j < kRobotPoses; ++j) {
      robot.push_back(linear.AddBlock(PoseAt(0.5 * j, 0.2 * j), [] { return new PoseManifold; }));
      for (int v = 0; v < 2; ++v) {
        Eigen::MatrixXd A_K = RandomMatrix(8, kN, &rng);
        if (singular) A_K.col(3).setZero();
        linear.AddTerm(
            {cam, robot[j], target, intrinsics},
            {RandomMatrix(8, 7, &rng), RandomMatrix(8, 7, &rng), RandomMatrix(8, 7, &rng), A_K},
            RandomMatrix(8, 1, &rng));
      }
    }
    for (int j = 0; j < kRobotPoses; ++j)
      linear.AddTerm({robot[j]}, {RandomMatrix(6, 7, &rng)}, RandomMatrix(6, 1, &rng));
    if (prior) {
      Eigen::Matrix2d L;
      L << 3.0, 0.0, 1.0, 2.0;
      Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2, kN);
      A.middleCols(2, 2) = L;
      linear.AddTerm({intrinsics}, {A}, L * Eigen::Vector2d(321.0, 239.0));
      principal_point_information = L.transpose() * L;
    }
    const std::vector<ceres::ResidualBlockId> ids = linear.Build(&problem);
    views.assign(ids.begin(), ids.begin() + 2 * kRobotPoses);
    for (int j = 0; j < kRobotPoses; ++j)
      robot_poses.push_back({linear.block(robot[j]), ids[2 * kRobotPoses + j]});
  }

  handeye::internal::Refinement Covariance(const RobotPrior& prior) {
    ConsiderCovariance nothing_held({}, Eigen::MatrixXd(), Eigen::MatrixXd());
    return Covariance(prior, &nothing_held);
  }
  handeye::internal::Refinement Covariance(const RobotPrior& prior,
                                           ConsiderCovariance* covariance) {
    handeye::internal::Refinement out;
    handeye::internal::SolutionCovariance(&problem, {linear.block(cam)}, linear.block(target),
                                          {linear.block(intrinsics)}, views, prior, robot_poses,
                                          covariance, 1, &out);
    return out;
  }

  /// A⁻¹ B A⁻¹ in tangent space, the prior rows of B weighed by D:
  /// (rotation, then translation) of (settled / prior σ)².
  Eigen::MatrixXd Sandwich(const RobotPrior& prior) const {
    const Eigen::MatrixXd J = linear.TangentJacobian();
    Eigen::VectorXd W = Eigen::VectorXd::Ones(J.rows());
    const double rotation = prior.settled_sigma_rad / prior.sigma_rad;
    const double translation = prior.settled_sigma_m / prior.sigma_m;
    for (int j = 0; j < kRobotPoses; ++j) {
      const int row = 16 * kRobotPoses + 6 * j;
      W.segment(row, 3).setConstant(rotation * rotation);
      W.segment(row + 3, 3).setConstant(translation * translation);
    }
    const Eigen::MatrixXd A_inverse = (J.transpose() * J).lu().inverse();
    return A_inverse * J.transpose() * W.asDiagonal() * J * A_inverse;
  }
  Eigen::MatrixXd Of(const Eigen::MatrixXd& C, int block) const {
    return C.block(linear.Offset(block), linear.Offset(block), linear.TangentSize(block),
                   linear.TangentSize(block));
  }

  LinearProblem linear;
  ceres::Problem problem;
  int cam = 0, target = 0, intrinsics = 0;
  std::vector<int> robot;
  std::vector<ceres::ResidualBlockId> views;
  std::vector<RobotPoseBlock> robot_poses;
  Eigen::Matrix2d principal_point_information = Eigen::Matrix2d::Zero();
};

RobotPrior Prior(double settled_m, double settled_rad) {
  RobotPrior prior;
  prior.sigma_m = 0.001;
  prior.sigma_rad = 0.002;
  prior.pixel_sigma_px = 0.5;
  prior.settled_sigma_m = settled_m;
  prior.settled_sigma_rad = settled_rad;
  return prior;
}

}  // namespace

TEST_CASE("SolutionCovariance: a settled robot σ gives the dense sandwich A⁻¹BA⁻¹") {
  JointCell cell(false);
  // Settled: translation 1.5× the prior's σ, rotation half of it.
  const RobotPrior settled = Prior(0.0015, 0.001);
  const RobotPrior as_solved = Prior(0.001, 0.002);
  const double variance_factor = handeye::internal::VarianceFactor(&cell.problem, cell.views);
  const handeye::internal::Refinement out = cell.Covariance(settled);
  REQUIRE(out.T_cam_mount_covariance.size() == 1);
  REQUIRE(out.T_cam_mount_covariance[0]);
  REQUIRE(out.T_holder_target_covariance);
  const Eigen::MatrixXd expected = variance_factor * cell.Sandwich(settled);
  const Eigen::MatrixXd plain = variance_factor * cell.Sandwich(as_solved);
  // The sandwich matters here: a covariance that ignored it would fail.
  REQUIRE_FALSE(cell.Of(expected, cell.cam).isApprox(cell.Of(plain, cell.cam), 0.01));
  CHECK(
      Eigen::MatrixXd(*out.T_cam_mount_covariance[0]).isApprox(cell.Of(expected, cell.cam), 1e-8));
  CHECK(Eigen::MatrixXd(*out.T_holder_target_covariance)
            .isApprox(cell.Of(expected, cell.target), 1e-8));
  // Intrinsics: 1σ of the four free ones, 0 for the held.
  const Eigen::MatrixXd C_K = cell.Of(expected, cell.intrinsics);
  for (int p = 0; p < kN; ++p)
    CHECK(out.intrinsics_sigma[0][p] == Approx(p < 4 ? std::sqrt(C_K(p, p)) : 0.0).epsilon(1e-8));
  // Nothing held: no part from held intrinsics, no shift.
  REQUIRE(out.T_cam_mount_intrinsics_covariance[0]);
  CHECK(out.T_cam_mount_intrinsics_covariance[0]->isZero(0));
  CHECK(out.T_cam_mount_intrinsics_shift[0]->isZero(0));

  SECTION("settled as solved: the plain inverse") {
    const handeye::internal::Refinement same = cell.Covariance(as_solved);
    REQUIRE(same.T_cam_mount_covariance[0]);
    CHECK(
        Eigen::MatrixXd(*same.T_cam_mount_covariance[0]).isApprox(cell.Of(plain, cell.cam), 1e-8));
  }
}

TEST_CASE("SolutionCovariance: intrinsics the views cannot see leave no covariance") {
  JointCell cell(true);
  const handeye::internal::Refinement out = cell.Covariance(Prior(0.0015, 0.001));
  REQUIRE(out.T_cam_mount_covariance.size() == 1);
  CHECK_FALSE(out.T_cam_mount_covariance[0]);
  CHECK_FALSE(out.T_holder_target_covariance);
  // Free intrinsics infinite, held ones exact.
  for (int p = 0; p < kN; ++p)
    CHECK(out.intrinsics_sigma[0][p] == (p < 4 ? std::numeric_limits<double>::infinity() : 0.0));
}

TEST_CASE("SolutionCovariance: held intrinsics under their own prior add what freeing them would") {
  // cx, cy held (consider coordinates) with Σ = σ² P⁻¹, the prior the
  // problem holds: held + considered is the covariance with them free.
  JointCell cell(false, true);
  const RobotPrior as_solved = Prior(0.001, 0.002);
  const double variance_factor = handeye::internal::VarianceFactor(&cell.problem, cell.views);
  const double* K = cell.linear.block(cell.intrinsics);
  ConsiderCovariance covariance({{K, {2, 3}}},
                                variance_factor * cell.principal_point_information.inverse(),
                                cell.principal_point_information);
  const handeye::internal::Refinement out = cell.Covariance(as_solved, &covariance);
  REQUIRE(out.T_cam_mount_covariance[0]);
  REQUIRE(out.T_cam_mount_intrinsics_covariance[0]);
  REQUIRE(out.T_holder_target_covariance);
  const Eigen::MatrixXd J = cell.linear.TangentJacobian();
  const Eigen::MatrixXd freed = variance_factor * (J.transpose() * J).lu().inverse();
  // Held: the tangent columns of cx and cy out.
  std::vector<int> free;
  for (int i = 0; i < J.cols(); ++i)
    if (i != cell.linear.Offset(cell.intrinsics) + 2 &&
        i != cell.linear.Offset(cell.intrinsics) + 3)
      free.push_back(i);
  const Eigen::MatrixXd J_free = J(Eigen::all, free);
  const Eigen::MatrixXd held = variance_factor * (J_free.transpose() * J_free).lu().inverse();
  const Eigen::MatrixXd cam_held = held.topLeftCorner(6, 6);
  REQUIRE_FALSE(cam_held.isApprox(cell.Of(freed, cell.cam), 0.01));
  CHECK(Eigen::MatrixXd(*out.T_cam_mount_covariance[0]).isApprox(cam_held, 1e-8));
  CHECK(Eigen::MatrixXd(*out.T_cam_mount_covariance[0] + *out.T_cam_mount_intrinsics_covariance[0])
            .isApprox(cell.Of(freed, cell.cam), 1e-8));
  // T_holder_target's covariance has the held inputs' part in it.
  CHECK(
      Eigen::MatrixXd(*out.T_holder_target_covariance).isApprox(cell.Of(freed, cell.target), 1e-8));
  // fx, fy from the solve with cx, cy held.
  const int k = cell.linear.Offset(cell.intrinsics);
  CHECK(out.intrinsics_sigma[0][0] == Approx(std::sqrt(held(k, k))).epsilon(1e-8));
  CHECK(out.intrinsics_sigma[0][1] == Approx(std::sqrt(held(k + 1, k + 1))).epsilon(1e-8));
  // cx, cy: their rows of the held covariance are 0 (up to rounding, which
  // the square root magnifies to about 1e-8 of fx's σ).
  CHECK(out.intrinsics_sigma[0][2] < 1e-6 * out.intrinsics_sigma[0][0]);
  CHECK(out.intrinsics_sigma[0][3] < 1e-6 * out.intrinsics_sigma[0][0]);
}
