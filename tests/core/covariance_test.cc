// SPDX-License-Identifier: GPL-2.0-or-later
// BlockCovariance (core/src/covariance.h) on problems linear in their
// parameters: its blocks are those of (JᵀJ)⁻¹ in the blocks' tangent spaces,
// it says when the Jacobian is rank deficient, and (Gauss-Markov) σ² times it
// is the spread of the least-squares estimate over noise draws.
#include "covariance.h"

#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "handeye/core/error.h"
#include "handeye/core/uncertainty.h"
#include "pose_manifold.h"
#include "support/linear_problem.h"
#include "support/projected_scene.h"

using handeye::internal::BlockCovariance;
using handeye::internal::PoseManifold;
using handeye::test::LinearProblem;
using handeye::test::RandomMatrix;

namespace {

Eigen::MatrixXd Inverse(const Eigen::MatrixXd& A) {
  return A.ldlt().solve(Eigen::MatrixXd::Identity(A.rows(), A.cols()));
}

/// The (a, b) block of the dense inverse of JᵀJ of `linear`.
Eigen::MatrixXd Expected(const LinearProblem& linear, const Eigen::MatrixXd& C, int a, int b) {
  return C.block(linear.Offset(a), linear.Offset(b), linear.TangentSize(a), linear.TangentSize(b));
}

}  // namespace

TEST_CASE("BlockCovariance: the blocks of a linear problem are those of (JᵀJ)⁻¹ in tangent space") {
  const ceres::CovarianceAlgorithmType algorithm = GENERATE(ceres::DENSE_SVD, ceres::SPARSE_QR);
  std::mt19937_64 rng(11);
  LinearProblem linear;
  const int x = linear.AddBlock({0.1, -0.2, 0.3});
  const int y = linear.AddBlock({1.0, 2.0});
  // z holds its third coordinate: a 3-dimensional tangent in a 4-vector.
  const int z =
      linear.AddBlock({0.5, 0.6, 0.7, 0.8}, [] { return new ceres::SubsetManifold(4, {2}); });
  linear.AddTerm({x, y}, {RandomMatrix(4, 3, &rng), RandomMatrix(4, 2, &rng)},
                 RandomMatrix(4, 1, &rng));
  linear.AddTerm({y, z}, {RandomMatrix(5, 2, &rng), RandomMatrix(5, 4, &rng)},
                 RandomMatrix(5, 1, &rng));
  linear.AddTerm({z}, {RandomMatrix(3, 4, &rng)}, RandomMatrix(3, 1, &rng));
  linear.AddTerm({x, z}, {RandomMatrix(4, 3, &rng), RandomMatrix(4, 4, &rng)},
                 RandomMatrix(4, 1, &rng));
  ceres::Problem problem;
  linear.Build(&problem);
  const double *px = linear.block(x), *py = linear.block(y), *pz = linear.block(z);
  const BlockCovariance covariance(&problem, {{px, px}, {px, py}, {py, pz}, {pz, pz}, {px, pz}},
                                   algorithm);
  REQUIRE(covariance.ok());

  const Eigen::MatrixXd J = linear.TangentJacobian();
  REQUIRE(J.cols() == 8);
  const Eigen::MatrixXd C = Inverse(J.transpose() * J);
  CHECK(covariance.Tangent(px, px).isApprox(Expected(linear, C, x, x), 1e-9));
  CHECK(covariance.Tangent(px, py).isApprox(Expected(linear, C, x, y), 1e-9));
  CHECK(covariance.Tangent(py, pz).isApprox(Expected(linear, C, y, z), 1e-9));
  CHECK(covariance.Tangent(pz, pz).isApprox(Expected(linear, C, z, z), 1e-9));
  // Asked the other way round: rows are the first block's.
  CHECK(covariance.Tangent(pz, px).isApprox(Expected(linear, C, z, x), 1e-9));
  // In the parameters: the held coordinate's row and column are 0.
  const Eigen::MatrixXd P = linear.PlusJacobian(z);
  const Eigen::MatrixXd ambient = covariance.Ambient(pz, pz);
  REQUIRE(ambient.rows() == 4);
  CHECK(ambient.isApprox(P * Expected(linear, C, z, z) * P.transpose(), 1e-9));
  CHECK(ambient.row(2).isZero(0));
  CHECK(ambient.col(2).isZero(0));
  CHECK(covariance.Ambient(px, pz).isApprox(Expected(linear, C, x, z) * P.transpose(), 1e-9));
}

TEST_CASE("BlockCovariance: a pose block's covariance is in the tangent of its current rotation") {
  std::mt19937_64 rng(12);
  LinearProblem linear;
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(Eigen::AngleAxisd(2.1, Eigen::Vector3d(1, -2, 0.5).normalized()));
  const int pose = linear.AddBlock({q.x(), q.y(), q.z(), q.w(), 0.3, -0.1, 1.2},
                                   [] { return new PoseManifold; });
  const int w = linear.AddBlock({0.0, 0.0});
  // Residuals linear in the 7 parameters: the tangent Jacobian is A·(d plus).
  linear.AddTerm({pose, w}, {RandomMatrix(9, 7, &rng), RandomMatrix(9, 2, &rng)},
                 RandomMatrix(9, 1, &rng));
  linear.AddTerm({w}, {RandomMatrix(2, 2, &rng)}, RandomMatrix(2, 1, &rng));
  ceres::Problem problem;
  linear.Build(&problem);
  const double *pp = linear.block(pose), *pw = linear.block(w);
  const BlockCovariance covariance(&problem, {{pp, pp}, {pp, pw}}, ceres::DENSE_SVD);
  REQUIRE(covariance.ok());
  const Eigen::MatrixXd J = linear.TangentJacobian();
  REQUIRE(J.cols() == 8);
  const Eigen::MatrixXd C = Inverse(J.transpose() * J);
  const Eigen::MatrixXd tangent = covariance.Tangent(pp, pp);
  REQUIRE(tangent.rows() == 6);
  CHECK(tangent.isApprox(Expected(linear, C, pose, pose), 1e-9));
  CHECK(covariance.Tangent(pp, pw).isApprox(Expected(linear, C, pose, w), 1e-9));
  const Eigen::MatrixXd P = linear.PlusJacobian(pose);
  CHECK(covariance.Ambient(pp, pp).isApprox(P * tangent * P.transpose(), 1e-9));
  // The quaternion moves only along the sphere: its covariance has no part
  // along q itself.
  const Eigen::Vector4d along(q.x(), q.y(), q.z(), q.w());
  CHECK((covariance.Ambient(pp, pp).topLeftCorner<4, 4>() * along).norm() < 1e-12);
}

TEST_CASE("BlockCovariance: a rank-deficient Jacobian gives no blocks") {
  const ceres::CovarianceAlgorithmType algorithm = GENERATE(ceres::DENSE_SVD, ceres::SPARSE_QR);
  const bool pinned = GENERATE(false, true);
  LinearProblem linear;
  const int a = linear.AddBlock({0.0});
  const int b = linear.AddBlock({0.0, 0.0});
  // a + b₀ is seen twice and b₁ once: a and b₀ apart are not, unless a is pinned.
  Eigen::Matrix<double, 3, 2> B;
  B << 1, 0, 2, 0, 0, 1;
  linear.AddTerm({a, b}, {Eigen::Vector3d(1, 2, 0), B}, Eigen::Vector3d(1, 2, 3));
  if (pinned) linear.AddTerm({a}, {Eigen::MatrixXd::Ones(1, 1)}, Eigen::VectorXd::Constant(1, 0.5));
  ceres::Problem problem;
  linear.Build(&problem);
  const double *pa = linear.block(a), *pb = linear.block(b);
  const BlockCovariance covariance(&problem, {{pa, pa}, {pa, pb}, {pb, pb}}, algorithm);
  CHECK(covariance.ok() == pinned);
}

TEST_CASE("BlockCovariance: fewer residuals than unknowns give no blocks") {
  // Rank deficient however the residuals fall: 2 residuals, 3 unknowns.
  const ceres::CovarianceAlgorithmType algorithm = GENERATE(ceres::DENSE_SVD, ceres::SPARSE_QR);
  std::mt19937_64 rng(14);
  LinearProblem linear;
  const int a = linear.AddBlock({0.0});
  const int b = linear.AddBlock({0.0, 0.0});
  linear.AddTerm({a, b}, {RandomMatrix(2, 1, &rng), RandomMatrix(2, 2, &rng)},
                 Eigen::Vector2d(1, 2));
  ceres::Problem problem;
  linear.Build(&problem);
  const double *pa = linear.block(a), *pb = linear.block(b);
  const BlockCovariance covariance(&problem, {{pa, pa}, {pa, pb}, {pb, pb}}, algorithm);
  CHECK_FALSE(covariance.ok());
}

TEST_CASE("The noise-only bound refuses views with fewer points than it has unknowns") {
  // One camera's pose and the target's: 12 unknowns. Three views of one
  // point give 6 residuals of full rank, which only the count shows singular.
  handeye::SyntheticScene scene = handeye::test::ProjectedScene("small", 1, 5, 31, 0.0);
  handeye::CalibrationResult at;
  handeye::CameraResult camera;
  camera.name = scene.dataset.cameras[0].name;
  camera.calibrated = true;
  camera.T_cam = scene.truth.T_cam.at(camera.name);
  at.cameras.push_back(camera);
  at.T_target = scene.truth.T_target;
  const size_t points = GENERATE(size_t{1}, size_t{40});
  auto& observations = scene.dataset.observations;
  REQUIRE(observations.size() >= 3);
  observations.resize(3);
  for (handeye::Observation& view : observations) {
    REQUIRE(view.ids.size() >= 40);
    view.ids.resize(points);
    view.points_px.resize(points);
  }
  if (points == 1) {
    CHECK_THROWS_AS(handeye::ComputePositionCovariance(scene.dataset, at, 0.3),
                    handeye::SolveError);
  } else {
    // The control: three views of 40 points do fix both poses.
    const handeye::PositionCovariance bound =
        handeye::ComputePositionCovariance(scene.dataset, at, 0.3);
    CHECK(bound.camera_position.at(camera.name).trace() > 0);
  }
}

TEST_CASE(
    "BlockCovariance: σ² times it is the spread of the least-squares estimate (Gauss-Markov)") {
  std::mt19937_64 rng(13);
  // Two blocks whose columns are far from orthogonal: a strong correlation.
  const Eigen::MatrixXd A = RandomMatrix(30, 2, &rng);
  Eigen::MatrixXd B = RandomMatrix(30, 1, &rng);
  B += 1.5 * A.col(0);
  const Eigen::Vector3d truth(0.4, -1.3, 2.0);
  const double sigma = 0.05;
  const Eigen::VectorXd exact = A * truth.head<2>() + B * truth.tail<1>();

  auto make = [&](const Eigen::VectorXd& observed, LinearProblem* linear) {
    const int x = linear->AddBlock({0.0, 0.0});
    const int y = linear->AddBlock({0.0});
    linear->AddTerm({x, y}, {A, B}, observed);
    return std::pair<int, int>(x, y);
  };
  const int draws = 200;
  std::normal_distribution<double> noise(0.0, sigma);
  Eigen::MatrixXd estimates(draws, 3);
  for (int d = 0; d < draws; ++d) {
    Eigen::VectorXd observed = exact;
    for (int i = 0; i < observed.size(); ++i) observed[i] += noise(rng);
    LinearProblem linear;
    const auto [x, y] = make(observed, &linear);
    ceres::Problem problem;
    linear.Build(&problem);
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_QR;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    REQUIRE(summary.IsSolutionUsable());
    estimates.row(d) << linear.block(x)[0], linear.block(x)[1], linear.block(y)[0];
  }
  LinearProblem linear;
  const auto [x, y] = make(exact, &linear);
  ceres::Problem problem;
  linear.Build(&problem);
  const double *px = linear.block(x), *py = linear.block(y);
  const BlockCovariance covariance(&problem, {{px, px}, {px, py}, {py, py}}, ceres::DENSE_SVD);
  REQUIRE(covariance.ok());
  Eigen::Matrix3d predicted;
  predicted << covariance.Tangent(px, px), covariance.Tangent(px, py), covariance.Tangent(py, px),
      covariance.Tangent(py, py);
  predicted *= sigma * sigma;

  const Eigen::RowVector3d mean = estimates.colwise().mean();
  const Eigen::MatrixXd centred = estimates.rowwise() - mean;
  const Eigen::Matrix3d sample = centred.transpose() * centred / (draws - 1);
  for (int i = 0; i < 3; ++i) {
    // Unbiased: the mean within 4 standard errors of the truth.
    CHECK(std::abs(mean[i] - truth[i]) < 4 * std::sqrt(predicted(i, i) / draws));
    // A variance from 200 draws has a relative σ of 10 %.
    CHECK(sample(i, i) == Approx(predicted(i, i)).epsilon(0.25));
  }
  // The correlation of x₀ and y (strong by design), within 0.15 (σ about 0.03).
  const double predicted_rho = predicted(0, 2) / std::sqrt(predicted(0, 0) * predicted(2, 2));
  const double sample_rho = sample(0, 2) / std::sqrt(sample(0, 0) * sample(2, 2));
  REQUIRE(std::abs(predicted_rho) > 0.5);
  CHECK(sample_rho == Approx(predicted_rho).margin(0.15));
}

TEST_CASE("Student's t quantiles are those of the tables", "[covariance]") {
  using handeye::internal::StudentUpperQuantile;
  // One-sided upper tails from the standard tables, and the Cauchy's
  // tan(π/4) at 1 degree of freedom.
  CHECK(StudentUpperQuantile(0.001, 12) == Approx(3.930).margin(5e-4));
  CHECK(StudentUpperQuantile(0.005, 30) == Approx(2.750).margin(5e-4));
  CHECK(StudentUpperQuantile(0.025, 3) == Approx(3.182).margin(5e-4));
  CHECK(StudentUpperQuantile(0.0005, 5) == Approx(6.869).margin(5e-4));
  CHECK(StudentUpperQuantile(0.25, 1) == Approx(1.0).margin(1e-6));
  // Many degrees of freedom: the normal's 3σ tail.
  CHECK(StudentUpperQuantile(0.5 * std::erfc(3.0 / std::sqrt(2.0)), 1e6) ==
        Approx(3.0).margin(1e-3));
}
