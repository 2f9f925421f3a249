// SPDX-License-Identifier: GPL-2.0-or-later
// Covariance blocks of a solved chain problem (covariance.h).

#include "covariance.h"

namespace handeye::internal {
namespace {

/// Fewer residuals than free tangent coordinates: JᵀJ is singular, which
/// DENSE_SVD does not see (Ceres' thin SVD of J has one singular value per
/// residual then, none of them 0, and it returns the pseudo-inverse).
bool FewerResidualsThanUnknowns(const ceres::Problem& problem) {
  std::vector<double*> blocks;
  problem.GetParameterBlocks(&blocks);
  int unknowns = 0;
  for (const double* block : blocks)
    if (!problem.IsParameterBlockConstant(block))
      unknowns += problem.ParameterBlockTangentSize(block);
  return problem.NumResiduals() < unknowns;
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
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> C(problem_->ParameterBlockTangentSize(a),
                                                                           problem_->ParameterBlockTangentSize(b));
  covariance_->GetCovarianceBlockInTangentSpace(a, b, C.data());
  return C;
}

Eigen::MatrixXd BlockCovariance::Ambient(const double* a, const double* b) const {
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> C(problem_->ParameterBlockSize(a),
                                                                           problem_->ParameterBlockSize(b));
  covariance_->GetCovarianceBlock(a, b, C.data());
  return C;
}

}  // namespace handeye::internal
