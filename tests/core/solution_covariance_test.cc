// SPDX-License-Identifier: GPL-2.0-or-later
// SolutionCovariance (core/src/refine_covariance.cc, refine_internal.h) on a
// problem linear in its parameters with the joint solve's blocks: a camera's
// T_cam_mount, T_holder_target, intrinsics with held parameters, and robot
// pose blocks under a prior. Where the robot's settled σ differs from the
// prior's, its block-wise sandwich must be the dense A⁻¹ B A⁻¹, B the
// information with the prior rows reweighted by (settled / prior σ)².
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

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

std::vector<double> PoseAt(double angle_rad, double x) {
  const Eigen::Quaterniond q(
      Eigen::AngleAxisd(angle_rad, Eigen::Vector3d(0.2, 1.0, -0.4).normalized()));
  return {q.x(), q.y(), q.z(), q.w(), x, 0.1, 0.9};
}

/// The blocks of a joint solve, each view seeing all of them linearly: 8
/// residuals per view, two views per robot pose; intrinsics fx, fy, cx, cy
/// free. `singular`: the views do not see cy (a zero column). `prior`: cx
/// and cy under a prior L (K₂,₃ − given) of information P = LᵀL. With fewer
/// than six robot poses their scatter is too rough to widen σ by.
struct JointCell {
  explicit JointCell(bool singular, bool prior = false, int poses = 3) : robot_pose_count(poses) {
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
    for (int j = 0; j < robot_pose_count; ++j) {
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
    for (int j = 0; j < robot_pose_count; ++j)
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
    views.assign(ids.begin(), ids.begin() + 2 * robot_pose_count);
    for (int j = 0; j < robot_pose_count; ++j) {
      robot_poses.push_back({linear.block(robot[j]), ids[2 * robot_pose_count + j]});
      at_pose.push_back({ids[2 * j], ids[2 * j + 1], ids[2 * robot_pose_count + j]});
    }
  }

  handeye::internal::Refinement Covariance(const RobotPrior& prior) {
    ConsiderCovariance nothing_held({}, Eigen::MatrixXd(), Eigen::MatrixXd());
    return Covariance(prior, &nothing_held);
  }
  handeye::internal::Refinement Covariance(const RobotPrior& prior,
                                           ConsiderCovariance* covariance) {
    handeye::internal::Refinement out;
    handeye::internal::SolutionCovariance(&problem, {linear.block(cam)}, linear.block(target),
                                          {linear.block(intrinsics)}, views, at_pose, prior,
                                          robot_poses, covariance, 1, &out);
    return out;
  }

  /// A⁻¹ B A⁻¹ in tangent space, the prior rows of B weighed by D:
  /// (rotation, then translation) of (settled / prior σ)².
  Eigen::MatrixXd Sandwich(const RobotPrior& prior) const {
    const Eigen::MatrixXd J = linear.TangentJacobian();
    Eigen::VectorXd W = Eigen::VectorXd::Ones(J.rows());
    const double rotation = prior.settled_sigma_rad / prior.sigma_rad;
    const double translation = prior.settled_sigma_m / prior.sigma_m;
    for (int j = 0; j < robot_pose_count; ++j) {
      const int row = 16 * robot_pose_count + 6 * j;
      W.segment(row, 3).setConstant(rotation * rotation);
      W.segment(row + 3, 3).setConstant(translation * translation);
    }
    const Eigen::MatrixXd A_inverse = (J.transpose() * J).lu().inverse();
    return A_inverse * J.transpose() * W.asDiagonal() * J * A_inverse;
  }
  /// The camera's covariance with these tangent coordinates of the
  /// intrinsics known: C_xx − C_xK C_KK⁻¹ C_Kx.
  Eigen::MatrixXd CamIntrinsicsKnown(const Eigen::MatrixXd& C, std::vector<int> known) const {
    for (int& i : known) i += linear.Offset(intrinsics);
    const Eigen::MatrixXd C_xK =
        C.block(linear.Offset(cam), 0, linear.TangentSize(cam), C.cols())(Eigen::all, known);
    return Of(C, cam) - C_xK * C(known, known).inverse() * C_xK.transpose();
  }
  /// The camera's whole covariance as reported: the solve's part and what
  /// the intrinsics' uncertainty adds.
  static Eigen::MatrixXd Total(const handeye::internal::Refinement& out) {
    return *out.T_cam_mount_covariance[0] + *out.T_cam_mount_intrinsics_covariance[0];
  }
  Eigen::MatrixXd Of(const Eigen::MatrixXd& C, int block) const {
    return C.block(linear.Offset(block), linear.Offset(block), linear.TangentSize(block),
                   linear.TangentSize(block));
  }

  const int robot_pose_count;
  LinearProblem linear;
  ceres::Problem problem;
  int cam = 0, target = 0, intrinsics = 0;
  std::vector<int> robot;
  std::vector<ceres::ResidualBlockId> views;
  std::vector<std::vector<ceres::ResidualBlockId>> at_pose;
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
  REQUIRE(out.T_cam_mount_intrinsics_covariance[0]);
  CHECK(JointCell::Total(out).isApprox(cell.Of(expected, cell.cam), 1e-8));
  // fx, fy, cx, cy refined: the solve's part is the camera's covariance
  // were they known; what they add is the intrinsics' part.
  const Eigen::MatrixXd known = cell.CamIntrinsicsKnown(expected, {0, 1, 2, 3});
  REQUIRE_FALSE(known.isApprox(cell.Of(expected, cell.cam), 0.01));
  CHECK(Eigen::MatrixXd(*out.T_cam_mount_covariance[0]).isApprox(known, 1e-7));
  CHECK(Eigen::MatrixXd(*out.T_holder_target_covariance)
            .isApprox(cell.Of(expected, cell.target), 1e-8));
  // Intrinsics: 1σ of the four free ones, 0 for the held.
  const Eigen::MatrixXd C_K = cell.Of(expected, cell.intrinsics);
  for (int p = 0; p < kN; ++p)
    CHECK(out.intrinsics_sigma[0][p] == Approx(p < 4 ? std::sqrt(C_K(p, p)) : 0.0).epsilon(1e-8));
  // Nothing held: no shift.
  CHECK(out.T_cam_mount_intrinsics_shift[0]->isZero(0));

  SECTION("settled as solved: the plain inverse") {
    const handeye::internal::Refinement same = cell.Covariance(as_solved);
    REQUIRE(same.T_cam_mount_covariance[0]);
    CHECK(JointCell::Total(same).isApprox(cell.Of(plain, cell.cam), 1e-8));
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
  // fx, fy refined: the solve's part holds them known too.
  const Eigen::MatrixXd C_xK = held.block(0, cell.linear.Offset(cell.intrinsics), 6, 2);
  const Eigen::MatrixXd C_KK =
      held.block(cell.linear.Offset(cell.intrinsics), cell.linear.Offset(cell.intrinsics), 2, 2);
  CHECK(Eigen::MatrixXd(*out.T_cam_mount_covariance[0])
            .isApprox(cam_held - C_xK * C_KK.inverse() * C_xK.transpose(), 1e-7));
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

TEST_CASE("SolutionCovariance: σ is widened to the robot poses' own scatter where that is larger") {
  // Eight robot poses at the solution: the scatter of each pose's share of
  // the gradient, A⁻¹ (Σ_j s_j s_jᵀ · 8/7) A⁻¹ with s_j centred, is a floor
  // for the trace of the rotation and of the translation part.
  JointCell cell(false, false, 8);
  ceres::Solver::Options options;
  options.max_num_iterations = 50;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &cell.problem, &summary);
  REQUIRE(summary.IsSolutionUsable());
  const RobotPrior as_solved = Prior(0.001, 0.002);
  const double variance_factor = handeye::internal::VarianceFactor(&cell.problem, cell.views);
  const handeye::internal::Refinement out = cell.Covariance(as_solved);
  REQUIRE(out.T_cam_mount_covariance[0]);
  REQUIRE(out.T_holder_target_covariance);

  const Eigen::MatrixXd J = cell.linear.TangentJacobian();
  const Eigen::VectorXd r = cell.linear.Residuals();
  const Eigen::MatrixXd A_inverse = (J.transpose() * J).lu().inverse();
  // Rows of each pose's terms: its two views (8 each), then its prior (6).
  Eigen::MatrixXd scores(J.cols(), 8);
  for (int j = 0; j < 8; ++j) {
    const Eigen::Index view_rows = 16 * j, prior_rows = 16 * 8 + 6 * j;
    scores.col(j) = J.middleRows(view_rows, 16).transpose() * r.segment(view_rows, 16) +
                    J.middleRows(prior_rows, 6).transpose() * r.segment(prior_rows, 6);
  }
  scores.colwise() -= scores.rowwise().mean();
  const Eigen::MatrixXd scatter = A_inverse * scores * scores.transpose() * A_inverse * (8.0 / 7.0);
  const Eigen::MatrixXd model = variance_factor * A_inverse;
  auto widening = [&](int block) {
    const Eigen::MatrixXd C = cell.Of(model, block), S = cell.Of(scatter, block);
    Eigen::VectorXd d(6);
    for (int part = 0; part < 2; ++part) {
      const double m = C.block(3 * part, 3 * part, 3, 3).trace(),
                   s = S.block(3 * part, 3 * part, 3, 3).trace();
      d.segment(3 * part, 3).setConstant(s > m ? std::sqrt(s / m) : 1.0);
    }
    return Eigen::MatrixXd(d.asDiagonal());
  };
  const Eigen::MatrixXd D_cam = widening(cell.cam), D_target = widening(cell.target);
  // The scatter is wider than the model here (the camera's rotation by 1 %,
  // the target by 6 and 15 %): a covariance that ignored it would fail.
  REQUIRE(D_cam.diagonal().maxCoeff() > 1.005);
  REQUIRE(D_target.diagonal().minCoeff() > 1.05);
  CHECK(JointCell::Total(out).isApprox(D_cam * cell.Of(model, cell.cam) * D_cam, 1e-6));
  CHECK(Eigen::MatrixXd(*out.T_cam_mount_covariance[0])
            .isApprox(D_cam * cell.CamIntrinsicsKnown(model, {0, 1, 2, 3}) * D_cam, 1e-6));
  CHECK(Eigen::MatrixXd(*out.T_holder_target_covariance)
            .isApprox(D_target * cell.Of(model, cell.target) * D_target, 1e-6));
  const Eigen::MatrixXd C_K = cell.Of(model, cell.intrinsics),
                        S_K = cell.Of(scatter, cell.intrinsics);
  for (int p = 0; p < 4; ++p)
    CHECK(out.intrinsics_sigma[0][p] ==
          Approx(std::sqrt(std::max(C_K(p, p), S_K(p, p)))).epsilon(1e-6));

  SECTION("five poses: too few to widen by") {
    JointCell few(false, false, 5);
    ceres::Solve(options, &few.problem, &summary);
    const double factor = handeye::internal::VarianceFactor(&few.problem, few.views);
    const handeye::internal::Refinement plain = few.Covariance(as_solved);
    const Eigen::MatrixXd J5 = few.linear.TangentJacobian();
    REQUIRE(plain.T_cam_mount_covariance[0]);
    CHECK(JointCell::Total(plain).isApprox(
        few.Of(factor * (J5.transpose() * J5).lu().inverse(), few.cam), 1e-8));
  }
}
