// SPDX-License-Identifier: GPL-2.0-or-later
// Covariance blocks of a solved chain problem (covariance.h).

#include "covariance.h"

namespace handeye::internal {

BlockCovariance::BlockCovariance(ceres::Problem* problem, const Pairs& pairs,
                                 ceres::CovarianceAlgorithmType algorithm, int threads)
    : problem_(problem) {
  ceres::Covariance::Options options;
  options.algorithm_type = algorithm;
  options.num_threads = threads;
  covariance_ = std::make_unique<ceres::Covariance>(options);
  ok_ = covariance_->Compute(pairs, problem_);
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
