// SPDX-License-Identifier: GPL-2.0-or-later
// Covariance blocks of a solved chain problem (covariance.h).

#include "covariance.h"

#include <ceres/cost_function.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace handeye::internal {
namespace {

/// The tangent coordinates of the problem's free parameter blocks.
int FreeTangentSize(const ceres::Problem& problem) {
  std::vector<double*> blocks;
  problem.GetParameterBlocks(&blocks);
  int free = 0;
  for (const double* block : blocks)
    if (!problem.IsParameterBlockConstant(block)) free += problem.ParameterBlockTangentSize(block);
  return free;
}

/// Fewer residuals than free tangent coordinates: JᵀJ is singular, which
/// DENSE_SVD does not see (Ceres' thin SVD of J has one singular value per
/// residual then, none of them 0, and it returns the pseudo-inverse).
bool FewerResidualsThanUnknowns(const ceres::Problem& problem) {
  return problem.NumResiduals() < FreeTangentSize(problem);
}

double ViewDesignFactor(const ceres::Problem& problem,
                        const std::vector<ceres::ResidualBlockId>& views) {
  // Per axis: s² over all points, and n·m² per view (m the view's mean
  // residual), which is s² on average when the points are independent and
  // grows with an error the view's points share.
  double sum_sq = 0, sum_view = 0;
  int points = 0, used = 0;
  std::vector<double> r;
  for (ceres::ResidualBlockId id : views) {
    r.resize(problem.GetCostFunctionForResidualBlock(id)->num_residuals());
    double cost;
    // With the loss: a camera's weight (RefineJoint) scales its residuals.
    if (!problem.EvaluateResidualBlock(id, true, &cost, r.data(), nullptr)) continue;
    const int n = static_cast<int>(r.size()) / 2;
    if (n < 2) continue;
    double mx = 0, my = 0;
    for (int i = 0; i < n; ++i) {
      mx += r[2 * i];
      my += r[2 * i + 1];
      sum_sq += r[2 * i] * r[2 * i] + r[2 * i + 1] * r[2 * i + 1];
    }
    mx /= n;
    my /= n;
    sum_view += n * (mx * mx + my * my);
    points += n;
    ++used;
  }
  if (used < 2 || sum_sq <= 0) return 1.0;
  return std::max(1.0, (sum_view / used) / (sum_sq / points));
}

}  // namespace

BlockCovariance::BlockCovariance(ceres::Problem* problem, const Pairs& pairs,
                                 ceres::CovarianceAlgorithmType algorithm, int threads)
    : problem_(problem) {
  ceres::Covariance::Options options;
  options.algorithm_type = algorithm;
  options.num_threads = threads;
  covariance_ = std::make_unique<ceres::Covariance>(options);
  ok_ = !FewerResidualsThanUnknowns(*problem) && covariance_->Compute(pairs, problem_);
}

BlockCovariance::~BlockCovariance() = default;

Eigen::MatrixXd BlockCovariance::Tangent(const double* a, const double* b) const {
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> C(
      problem_->ParameterBlockTangentSize(a), problem_->ParameterBlockTangentSize(b));
  covariance_->GetCovarianceBlockInTangentSpace(a, b, C.data());
  return C;
}

Eigen::MatrixXd BlockCovariance::Ambient(const double* a, const double* b) const {
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> C(
      problem_->ParameterBlockSize(a), problem_->ParameterBlockSize(b));
  covariance_->GetCovarianceBlock(a, b, C.data());
  return C;
}

double VarianceFactor(ceres::Problem* problem, const std::vector<ceres::ResidualBlockId>& views) {
  double cost = 0;
  problem->Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, nullptr);
  const int redundancy = problem->NumResiduals() - FreeTangentSize(*problem);
  return (redundancy > 0 ? 2.0 * cost / redundancy : 1.0) * ViewDesignFactor(*problem, views);
}

double StudentUpperQuantile(double tail, double dof) {
  const double log_norm =
      std::lgamma(0.5 * (dof + 1)) - std::lgamma(0.5 * dof) - 0.5 * std::log(dof * M_PI);
  // 1/2 less the density's integral over [0, t], by Simpson's rule.
  const auto upper_tail = [&](double t) {
    constexpr int kSteps = 2000;  // even
    const double h = t / kSteps;
    double sum = 0;
    for (int i = 0; i <= kSteps; ++i) {
      const double x = i * h;
      const double density = std::exp(log_norm - 0.5 * (dof + 1) * std::log1p(x * x / dof));
      sum += density * (i == 0 || i == kSteps ? 1 : i % 2 ? 4 : 2);
    }
    return 0.5 - sum * h / 3.0;
  };
  double low = 0, high = 4;
  while (upper_tail(high) > tail) low = high, high *= 2;
  for (int i = 0; i < 50; ++i) {  // bisection, to far below any threshold's meaning
    const double mid = 0.5 * (low + high);
    (upper_tail(mid) > tail ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

}  // namespace handeye::internal
