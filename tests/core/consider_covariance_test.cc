// SPDX-License-Identifier: GPL-2.0-or-later
// ConsiderCovariance (core/src/consider_covariance.h) on problems linear in
// their parameters, against its formulas worked by hand from the Jacobian:
// with free coordinates F and held uncertain ones K, H = JᵀJ,
//   A⁻¹ = H_FF⁻¹,  G = H_FF⁻¹ H_FK,  S = H_KK − P − H_KF G,
//   Σ_post = (Σ⁻¹ + S/σ²)⁻¹,  Consider = G Σ_post Gᵀ,  Shift = G δc with
//   δc = −Σ_post g_K/σ², g = Jᵀr;
// and the laws they stand for.
#include "consider_covariance.h"

#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <memory>
#include <random>

#include "support/linear_problem.h"

using handeye::internal::ConsiderCovariance;
using handeye::test::LinearProblem;
using handeye::test::RandomMatrix;

namespace {

Eigen::MatrixXd LuInverse(const Eigen::MatrixXd& A) { return A.lu().inverse(); }

/// The formulas of the file comment for tangent Jacobian J and residuals r.
/// `error` extends G to every tangent coordinate: a held one's error is
/// minus its input's (row −e_k), so Consider and Shift of a block with held
/// coordinates hold their own Σ_post and δc.
struct Hand {
  Hand(const Eigen::MatrixXd& J, const Eigen::VectorXd& r, const std::vector<int>& F,
       const std::vector<int>& K, const Eigen::MatrixXd& P, const Eigen::MatrixXd& sigma,
       double variance_factor)
      : free(F) {
    const Eigen::MatrixXd H = J.transpose() * J;
    held = LuInverse(H(F, F));
    G = held * H(F, K);
    S = H(K, K) - P - H(K, F) * G;
    posterior = LuInverse(LuInverse(sigma) + S / variance_factor);
    const Eigen::VectorXd g = J.transpose() * r;
    delta_c = -posterior * g(K) / variance_factor;
    const int k = static_cast<int>(K.size());
    Eigen::MatrixXd error(J.cols(), k);
    error(F, Eigen::all) = G;
    error(K, Eigen::all) = -Eigen::MatrixXd::Identity(k, k);
    consider = error * posterior * error.transpose();
    shift = error * delta_c;
  }
  /// Rows of `M` (one per free coordinate) for the tangent coordinates
  /// offset … offset + n − 1; those held are 0.
  Eigen::MatrixXd Rows(const Eigen::MatrixXd& M, int offset, int n) const {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, M.cols());
    for (int i = 0; i < n; ++i) {
      const auto at = std::find(free.begin(), free.end(), offset + i);
      if (at != free.end()) out.row(i) = M.row(at - free.begin());
    }
    return out;
  }
  /// Rows and columns of A⁻¹ for two blocks' tangent coordinates.
  Eigen::MatrixXd Held(int offset_a, int n_a, int offset_b, int n_b) const {
    return Rows(Rows(held, offset_a, n_a).transpose(), offset_b, n_b).transpose();
  }

  std::vector<int> free;
  Eigen::MatrixXd held, G, S, posterior;
  Eigen::VectorXd delta_c;
  /// Over every tangent coordinate, free or held.
  Eigen::MatrixXd consider;
  Eigen::VectorXd shift;
};

/// An estimate x (3) and a held input c (2) seen together by 10 residuals, c
/// under a prior L(c − c₀) of information P = LᵀL; c at `held`, x at its
/// optimum for that c.
struct HeldInput {
  HeldInput(std::uint64_t seed, const Eigen::Vector2d& held) {
    std::mt19937_64 rng(seed);
    const int x_index = linear.AddBlock({0.0, 0.0, 0.0});
    const int c_index = linear.AddBlock({held[0], held[1]});
    linear.AddTerm({x_index, c_index}, {RandomMatrix(10, 3, &rng), RandomMatrix(10, 2, &rng)},
                   RandomMatrix(10, 1, &rng));
    Eigen::Matrix2d L;
    L << 2.0, 0.0, 0.7, 3.0;
    linear.AddTerm({c_index}, {L}, L * Eigen::Vector2d(0.9, -0.4));
    P = L.transpose() * L;
    x = linear.block(x_index);
    c = linear.block(c_index);
    const Eigen::MatrixXd J_x = linear.TangentJacobian().leftCols(3);
    const Eigen::VectorXd step =
        -(J_x.transpose() * J_x).ldlt().solve(J_x.transpose() * linear.Residuals());
    std::copy(step.data(), step.data() + 3, x);
    linear.Build(&problem);
  }
  Hand Formulas(const Eigen::MatrixXd& sigma, double variance_factor) const {
    return Hand(linear.TangentJacobian(), linear.Residuals(), {0, 1, 2}, {3, 4}, P, sigma,
                variance_factor);
  }
  /// The consider covariance of x with c's error of covariance `sigma`.
  std::unique_ptr<ConsiderCovariance> Computed(const Eigen::MatrixXd& sigma) {
    auto covariance = std::make_unique<ConsiderCovariance>(
        std::vector<ConsiderCovariance::Coordinates>{{c, {0, 1}}}, sigma, P);
    REQUIRE(covariance->Compute({{x, x}}, &problem, 1));
    return covariance;
  }

  LinearProblem linear;
  ceres::Problem problem;
  double *x = nullptr, *c = nullptr;
  Eigen::Matrix2d P;
};

Eigen::Matrix2d SomeSigma() {
  Eigen::Matrix2d sigma;
  sigma << 0.09, 0.02, 0.02, 0.04;
  return sigma;
}

}  // namespace

TEST_CASE("ConsiderCovariance: Block holds the inputs, Consider adds G Σ_post Gᵀ") {
  HeldInput cell(21, Eigen::Vector2d(1.0, -0.5));
  const double variance_factor = 0.7;
  const auto covariance = cell.Computed(SomeSigma());
  const Hand hand = cell.Formulas(SomeSigma(), variance_factor);
  // The held inputs are no unknowns: A_xx⁻¹, and nothing against c.
  CHECK(covariance->Block(cell.x, cell.x).isApprox(hand.held, 1e-9));
  CHECK(covariance->Block(cell.x, cell.c).norm() < 1e-9 * hand.held.norm());
  CHECK(covariance->Block(cell.c, cell.c).norm() < 1e-9 * hand.held.norm());
  const Eigen::MatrixXd consider = covariance->Consider(cell.x, variance_factor);
  CHECK(consider.isApprox(hand.consider.topLeftCorner(3, 3), 1e-9));
  // What the views say of c counts: the prior's Σ alone would add more.
  CHECK((hand.G * SomeSigma() * hand.G.transpose() - consider).trace() > 0);
}

TEST_CASE("ConsiderCovariance: with Σ the problem's own prior, held + considered is c freed") {
  // Σ = σ² P⁻¹: the estimate that refines c under its prior has covariance
  // σ² H⁻¹_xx = σ² (A_xx⁻¹ + G (S + P)⁻¹ Gᵀ).
  const double variance_factor = GENERATE(0.7, 3.0);
  HeldInput cell(22, Eigen::Vector2d(1.0, -0.5));
  const auto covariance = cell.Computed(variance_factor * LuInverse(cell.P));
  const Eigen::MatrixXd J = cell.linear.TangentJacobian();
  const Eigen::MatrixXd freed = LuInverse(J.transpose() * J).topLeftCorner(3, 3);
  CHECK((variance_factor * covariance->Block(cell.x, cell.x) +
         covariance->Consider(cell.x, variance_factor))
            .isApprox(variance_factor * freed, 1e-9));
}

TEST_CASE("ConsiderCovariance: Shift is G δc, what freeing c would take off the estimate") {
  // Off the minimum in c only: x at its optimum for the held c.
  HeldInput cell(23, Eigen::Vector2d(1.3, -0.1));
  const Eigen::MatrixXd J = cell.linear.TangentJacobian();
  const Eigen::VectorXd r = cell.linear.Residuals();
  REQUIRE((J.leftCols(3).transpose() * r).norm() < 1e-9);
  REQUIRE((J.rightCols(2).transpose() * r).norm() > 0.1);
  const double variance_factor = 0.7;
  SECTION("any Σ: the hand formula") {
    CHECK(cell.Computed(SomeSigma())
              ->Shift(cell.x, variance_factor)
              .isApprox(cell.Formulas(SomeSigma(), variance_factor).shift.head(3), 1e-9));
  }
  SECTION("Σ the problem's own prior: the held estimate less the one with c freed") {
    const auto covariance = cell.Computed(variance_factor * LuInverse(cell.P));
    // The linear problem's minimum with x and c free, one Gauss-Newton step away.
    const Eigen::VectorXd step = -(J.transpose() * J).ldlt().solve(J.transpose() * r);
    CHECK(covariance->Shift(cell.x, variance_factor).isApprox(-step.head(3), 1e-9));
  }
}

TEST_CASE("ConsiderCovariance: a known input adds nothing, an unknown one what the views leave") {
  HeldInput cell(24, Eigen::Vector2d(1.3, -0.1));
  const double variance_factor = 0.7;
  auto consider = [&](double scale) {
    const auto covariance = cell.Computed(scale * SomeSigma());
    return std::make_pair(covariance->Consider(cell.x, variance_factor),
                          covariance->Shift(cell.x, variance_factor));
  };
  const auto [reference, reference_shift] = consider(1.0);
  REQUIRE(reference.norm() > 1e-3);
  REQUIRE(reference_shift.norm() > 1e-3);
  // Σ → 0: nothing to add, nothing to shift, in proportion to Σ.
  const auto [known, known_shift] = consider(1e-8);
  CHECK(known.norm() < 2e-8 * reference.norm());
  CHECK(known_shift.norm() < 2e-8 * reference_shift.norm());
  // Σ → ∞: c as the views alone know it, σ² G S⁻¹ Gᵀ (finite).
  const Hand hand = cell.Formulas(SomeSigma(), variance_factor);
  const Eigen::MatrixXd views_only =
      variance_factor * hand.G * LuInverse(hand.S) * hand.G.transpose();
  CHECK(consider(1e8).first.isApprox(views_only, 1e-6));
}

TEST_CASE("ConsiderCovariance: independent inputs are held, and add G_r Σ_r Gᵀ_r at their own Σ") {
  // x (3) estimated; c (2) a given input under a prior (posterior Σ, as
  // above); r (3) an input of the second kind (a robot pose held as
  // reported), all seen by the same 12 residuals.
  std::mt19937_64 rng(27);
  LinearProblem linear;
  const int x_index = linear.AddBlock({0.0, 0.0, 0.0});
  const int c_index = linear.AddBlock({1.1, -0.3});
  const int r_index = linear.AddBlock({0.2, 0.1, -0.4});
  linear.AddTerm({x_index, c_index, r_index},
                 {RandomMatrix(12, 3, &rng), RandomMatrix(12, 2, &rng), RandomMatrix(12, 3, &rng)},
                 RandomMatrix(12, 1, &rng));
  Eigen::Matrix2d L;
  L << 2.0, 0.0, 0.7, 3.0;
  linear.AddTerm({c_index}, {L}, L * Eigen::Vector2d(0.9, -0.4));
  const Eigen::Matrix3d L_r = 4.0 * Eigen::Matrix3d::Identity();
  linear.AddTerm({r_index}, {L_r}, L_r * Eigen::Vector3d(0.2, 0.1, -0.4));
  double* x = linear.block(x_index);
  {
    const Eigen::MatrixXd J_x = linear.TangentJacobian().leftCols(3);
    const Eigen::VectorXd step =
        -(J_x.transpose() * J_x).ldlt().solve(J_x.transpose() * linear.Residuals());
    std::copy(step.data(), step.data() + 3, x);
  }
  ceres::Problem problem;
  linear.Build(&problem);
  Eigen::Matrix3d sigma_r;
  sigma_r << 0.05, 0.01, 0.0, 0.01, 0.08, -0.02, 0.0, -0.02, 0.03;
  ConsiderCovariance covariance({{linear.block(c_index), {0, 1}}}, SomeSigma(),
                                L.transpose() * L);
  covariance.HoldIndependent({{linear.block(r_index), {0, 1, 2}}}, sigma_r);
  REQUIRE(covariance.Compute({{x, x}}, &problem, 1));

  const Eigen::MatrixXd J = linear.TangentJacobian();
  const double variance_factor = 0.7;
  // c's formulas with r held where it is (its columns no unknowns).
  const Hand hand(J, linear.Residuals(), {0, 1, 2}, {3, 4}, L.transpose() * L, SomeSigma(),
                  variance_factor);
  const Eigen::MatrixXd H = J.transpose() * J;
  const std::vector<int> F = {0, 1, 2}, R = {5, 6, 7};
  const Eigen::MatrixXd G_r = LuInverse(H(F, F)) * H(F, R);
  CHECK(covariance.Block(x, x).isApprox(hand.held, 1e-9));
  CHECK(covariance.Consider(x, variance_factor).isApprox(hand.consider.topLeftCorner(3, 3), 1e-9));
  CHECK(covariance.Shift(x, variance_factor).isApprox(hand.shift.head(3), 1e-9));
  CHECK(covariance.Independent(x, x).isApprox(G_r * sigma_r * G_r.transpose(), 1e-9));
  // Held names the given intrinsics' coordinates only.
  CHECK(covariance.Held(linear.block(r_index)).empty());
  CHECK(covariance.Held(linear.block(c_index)) == std::vector<int>{0, 1});
}

TEST_CASE("ConsiderCovariance: some coordinates of two blocks held, one on a manifold") {
  // c holds its first parameter (a subset manifold) and is held in its second
  // tangent coordinate; d is held in both. Free: x and c's first tangent coordinate.
  std::mt19937_64 rng(25);
  LinearProblem linear;
  const int x = linear.AddBlock({0.2, 0.1, -0.3});
  const int c = linear.AddBlock({4.0, 1.0, -0.5}, [] { return new ceres::SubsetManifold(3, {0}); });
  const int d = linear.AddBlock({0.3, 0.6});
  linear.AddTerm({x, c, d},
                 {RandomMatrix(12, 3, &rng), RandomMatrix(12, 3, &rng), RandomMatrix(12, 2, &rng)},
                 RandomMatrix(12, 1, &rng));
  const Eigen::Vector3d prior_c(5.0, 2.0, 4.0);
  const Eigen::Vector2d prior_d(3.0, 6.0);
  linear.AddTerm({c}, {Eigen::MatrixXd(prior_c.asDiagonal())}, Eigen::Vector3d(20.0, 1.8, -2.4));
  linear.AddTerm({d}, {Eigen::MatrixXd(prior_d.asDiagonal())}, Eigen::Vector2d(0.6, 4.0));
  ceres::Problem problem;
  linear.Build(&problem);
  const double *px = linear.block(x), *pc = linear.block(c), *pd = linear.block(d);
  REQUIRE(problem.ParameterBlockTangentSize(pc) == 2);
  // Tangent columns: x 0–2, c 3–4 (its 2nd and 3rd parameters), d 5–6; held: c's 4, d's 5, 6.
  Eigen::Matrix3d P = Eigen::Vector3d(16.0, 9.0, 36.0).asDiagonal();
  Eigen::Matrix3d sigma;
  sigma << 0.05, 0.01, 0.0, 0.01, 0.08, -0.02, 0.0, -0.02, 0.03;
  const double variance_factor = 1.7;
  ConsiderCovariance covariance({{pc, {1}}, {pd, {0, 1}}}, sigma, P);
  REQUIRE(covariance.Compute({{px, px}, {pc, pc}, {px, pc}}, &problem, 1));
  const Hand hand(linear.TangentJacobian(), linear.Residuals(), {0, 1, 2, 3}, {4, 5, 6}, P, sigma,
                  variance_factor);
  CHECK(covariance.Block(px, px).isApprox(hand.Held(0, 3, 0, 3), 1e-9));
  CHECK(covariance.Block(px, pc).isApprox(hand.Held(0, 3, 3, 2), 1e-9));
  const Eigen::MatrixXd block_c = covariance.Block(pc, pc);
  CHECK(block_c(0, 0) == Approx(hand.held(3, 3)).epsilon(1e-9));
  CHECK(std::abs(block_c(1, 1)) < 1e-12);
  CHECK(covariance.Consider(px, variance_factor).isApprox(hand.consider.block(0, 0, 3, 3), 1e-9));
  // c's held coordinate adds its own Σ_post, and its tie to c's free one.
  CHECK(covariance.Consider(pc, variance_factor).isApprox(hand.consider.block(3, 3, 2, 2), 1e-9));
  CHECK(covariance.Consider(pc, variance_factor)(1, 1) ==
        Approx(hand.posterior(0, 0)).epsilon(1e-9));
  // Off the minimum (the values above are not it), the formula for Shift
  // reads the gradient per block and coordinate.
  CHECK(covariance.Shift(px, variance_factor).isApprox(hand.shift.head(3), 1e-9));
  CHECK(covariance.Shift(pc, variance_factor).isApprox(hand.shift.segment(3, 2), 1e-9));
  // Shift by input: a column per ambient coordinate of the held block, G's
  // column times that input's δc, and the columns of every held block sum to
  // the shift (c's first two ambient coordinates are not held).
  const Eigen::MatrixXd of_c = covariance.ShiftOf(px, pc, variance_factor);
  const Eigen::MatrixXd of_d = covariance.ShiftOf(px, pd, variance_factor);
  REQUIRE(of_c.rows() == 3);
  REQUIRE(of_c.cols() == 3);
  REQUIRE(of_d.cols() == 2);
  CHECK(of_c.leftCols(2).norm() < 1e-12);
  CHECK(of_c.col(2).isApprox(hand.G.block(0, 0, 3, 1) * hand.delta_c[0], 1e-9));
  CHECK(of_d.col(1).isApprox(hand.G.block(0, 2, 3, 1) * hand.delta_c[2], 1e-9));
  CHECK((of_c.rowwise().sum() + of_d.rowwise().sum())
            .isApprox(covariance.Shift(px, variance_factor), 1e-9));
}
