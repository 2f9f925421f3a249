// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A least-squares problem linear in its parameters, r = Σ_k A_k p_k − b, for
// the tests of the covariance machinery: its Jacobian is known exactly, so
// the covariances Ceres computes can be checked against a dense inverse.

#include <ceres/cost_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <random>
#include <vector>

namespace handeye::test {

/// A matrix of independent standard normal entries from `rng`.
inline Eigen::MatrixXd RandomMatrix(int rows, int cols, std::mt19937_64* rng) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd M(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) M(i, j) = normal(*rng);
  return M;
}

/// r = Σ_k A_k p_k − b over the parameter blocks p_k.
class LinearCost : public ceres::CostFunction {
 public:
  LinearCost(std::vector<Eigen::MatrixXd> A, Eigen::VectorXd b)
      : A_(std::move(A)), b_(std::move(b)) {
    set_num_residuals(static_cast<int>(b_.size()));
    for (const Eigen::MatrixXd& A_k : A_) mutable_parameter_block_sizes()->push_back(A_k.cols());
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    Eigen::Map<Eigen::VectorXd> r(residuals, b_.size());
    r = -b_;
    for (size_t k = 0; k < A_.size(); ++k) {
      r += A_[k] * Eigen::Map<const Eigen::VectorXd>(parameters[k], A_[k].cols());
      if (jacobians && jacobians[k])
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            jacobians[k], A_[k].rows(), A_[k].cols()) = A_[k];
    }
    return true;
  }

 private:
  std::vector<Eigen::MatrixXd> A_;
  Eigen::VectorXd b_;
};

/// Parameter blocks (each maybe on a manifold) and linear terms over them;
/// builds the Ceres problem and, apart from Ceres, its Jacobian in the
/// blocks' tangent spaces (columns in the order the blocks were added).
class LinearProblem {
 public:
  using MakeManifold = std::function<ceres::Manifold*()>;
  struct Term {
    std::vector<int> blocks;
    std::vector<Eigen::MatrixXd> A;
    Eigen::VectorXd b;
  };

  /// A block at `values`, on the manifold `make()` (none when empty).
  int AddBlock(std::vector<double> values, MakeManifold make = {}) {
    values_.push_back(std::move(values));
    manifolds_.push_back(std::move(make));
    return static_cast<int>(values_.size()) - 1;
  }
  void AddTerm(std::vector<int> blocks, std::vector<Eigen::MatrixXd> A, Eigen::VectorXd b) {
    terms_.push_back({std::move(blocks), std::move(A), std::move(b)});
  }
  double* block(int k) { return values_[k].data(); }
  const std::vector<Term>& terms() const { return terms_; }

  /// Adds the blocks and the terms to `problem` (which takes the manifolds
  /// and costs it is given); returns the terms' residual blocks.
  std::vector<ceres::ResidualBlockId> Build(ceres::Problem* problem) {
    for (size_t k = 0; k < values_.size(); ++k)
      problem->AddParameterBlock(values_[k].data(), static_cast<int>(values_[k].size()),
                                 manifolds_[k] ? manifolds_[k]() : nullptr);
    std::vector<ceres::ResidualBlockId> ids;
    for (const Term& term : terms_) {
      std::vector<double*> blocks;
      for (int k : term.blocks) blocks.push_back(values_[k].data());
      ids.push_back(problem->AddResidualBlock(new LinearCost(term.A, term.b), nullptr, blocks));
    }
    return ids;
  }

  /// d(ambient) / d(tangent) of block k at its values (the identity off manifolds).
  Eigen::MatrixXd PlusJacobian(int k) const {
    const int n = static_cast<int>(values_[k].size());
    if (!manifolds_[k]) return Eigen::MatrixXd::Identity(n, n);
    const std::unique_ptr<ceres::Manifold> manifold(manifolds_[k]());
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> P(
        n, manifold->TangentSize());
    manifold->PlusJacobian(values_[k].data(), P.data());
    return P;
  }
  int TangentSize(int k) const { return static_cast<int>(PlusJacobian(k).cols()); }
  /// The first column of block k in the tangent Jacobian.
  int Offset(int k) const {
    int offset = 0;
    for (int j = 0; j < k; ++j) offset += TangentSize(j);
    return offset;
  }

  /// The stacked residuals of every term at the blocks' values.
  Eigen::VectorXd Residuals() const {
    std::vector<double> stacked;
    for (const Term& term : terms_) {
      Eigen::VectorXd r = -term.b;
      for (size_t i = 0; i < term.blocks.size(); ++i)
        r += term.A[i] *
             Eigen::Map<const Eigen::VectorXd>(values_[term.blocks[i]].data(), term.A[i].cols());
      stacked.insert(stacked.end(), r.data(), r.data() + r.size());
    }
    return Eigen::Map<Eigen::VectorXd>(stacked.data(), static_cast<Eigen::Index>(stacked.size()));
  }

  /// The stacked Jacobian of every term in the blocks' tangent spaces.
  Eigen::MatrixXd TangentJacobian() const {
    int rows = 0;
    for (const Term& term : terms_) rows += static_cast<int>(term.b.size());
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(rows, Offset(static_cast<int>(values_.size())));
    int row = 0;
    for (const Term& term : terms_) {
      for (size_t i = 0; i < term.blocks.size(); ++i) {
        const int k = term.blocks[i];
        J.block(row, Offset(k), term.b.size(), TangentSize(k)) += term.A[i] * PlusJacobian(k);
      }
      row += static_cast<int>(term.b.size());
    }
    return J;
  }

 private:
  std::vector<std::vector<double>> values_;
  std::vector<MakeManifold> manifolds_;
  std::vector<Term> terms_;
};

}  // namespace handeye::test
