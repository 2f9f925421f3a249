// SPDX-License-Identifier: GPL-2.0-or-later
#include "consider_covariance.h"

#include <ceres/manifold.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <map>
#include <set>

namespace handeye::internal {

ConsiderCovariance::ConsiderCovariance(std::vector<Coordinates> consider, Eigen::MatrixXd sigma,
                                       Eigen::MatrixXd prior_information)
    : consider_(std::move(consider)), sigma_(std::move(sigma)), prior_information_(std::move(prior_information)) {
  for (const Coordinates& c : consider_) num_consider_ += static_cast<int>(c.tangent.size());
  num_posterior_ = num_consider_;
  posterior_blocks_ = consider_.size();
}

void ConsiderCovariance::HoldIndependent(const std::vector<Coordinates>& independent,
                                         Eigen::MatrixXd independent_sigma) {
  for (const Coordinates& c : independent) {
    consider_.push_back(c);
    num_consider_ += static_cast<int>(c.tangent.size());
  }
  independent_sigma_ = std::move(independent_sigma);
}

bool ConsiderCovariance::Compute(const std::vector<std::pair<const double*, const double*>>& pairs,
                                 ceres::Problem* problem, int threads) {
  problem_ = problem;
  // Ceres wants each unordered pair once.
  std::set<std::pair<const double*, const double*>> wanted;
  auto want = [&](const double* a, const double* b) { wanted.insert(std::minmax(a, b)); };
  std::set<const double*> blocks;
  for (const auto& [a, b] : pairs) {
    want(a, b);
    blocks.insert(a);
    blocks.insert(b);
  }
  for (const Coordinates& c : consider_) {
    for (const double* block : blocks) want(block, c.block);
    for (const Coordinates& d : consider_) want(c.block, d.block);
  }
  covariance_ = std::make_unique<BlockCovariance>(
      problem, BlockCovariance::Pairs(wanted.begin(), wanted.end()), ceres::SPARSE_QR, threads);
  against_.clear();
  if (!covariance_->ok()) return false;
  if (num_consider_ == 0) return true;
  // Each block's rows against the consider coordinates, read once: the
  // scatter reads every block against every other (32 cameras: 17 000 times).
  for (const double* block : blocks) against_.emplace(block, AgainstConsider(block));
  for (const Coordinates& c : consider_) against_.emplace(c.block, AgainstConsider(c.block));
  Eigen::MatrixXd H_cc(num_consider_, num_consider_);
  int row = 0;
  for (const Coordinates& c : consider_) {
    const Eigen::MatrixXd rows = AgainstConsider(c.block);
    for (int i : c.tangent) H_cc.row(row++) = rows.row(i);
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(H_cc);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all()) return false;
  inverse_cc_ = ldlt.solve(Eigen::MatrixXd::Identity(num_consider_, num_consider_));
  // g_c: the cost's gradient in the given intrinsics' tangent spaces.
  gradient_.resize(num_posterior_);
  if (num_posterior_ == 0) return true;
  ceres::Problem::EvaluateOptions evaluate;
  for (size_t b = 0; b < posterior_blocks_; ++b)
    evaluate.parameter_blocks.push_back(const_cast<double*>(consider_[b].block));
  std::vector<double> gradient;
  double cost = 0;
  if (!problem->Evaluate(evaluate, &cost, nullptr, &gradient, nullptr)) return false;
  int at = 0, offset = 0;
  for (size_t b = 0; b < posterior_blocks_; ++b) {
    for (int i : consider_[b].tangent) gradient_[at++] = gradient[offset + i];
    offset += problem->ParameterBlockTangentSize(consider_[b].block);
  }
  return true;
}

Eigen::MatrixXd ConsiderCovariance::Posterior(double variance_factor) const {
  // (Σ⁻¹ + S/σ²)⁻¹ = (I + Σ S/σ²)⁻¹ Σ: no inverse of Σ (the focal length's is
  // singular: one error for fx and fy) nor of S (views may not inform c).
  // S of the given intrinsics with the independent inputs held: the
  // top-left block of (H⁻¹_cc)⁻¹.
  const Eigen::MatrixXd S =
      inverse_cc_.topLeftCorner(num_posterior_, num_posterior_) - prior_information_;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(num_posterior_, num_posterior_);
  const Eigen::MatrixXd posterior = (I + sigma_ * S / variance_factor).lu().solve(sigma_);
  return 0.5 * (posterior + posterior.transpose());
}

Eigen::MatrixXd ConsiderCovariance::Raw(const double* a, const double* b) const {
  return covariance_->Tangent(a, b);
}

Eigen::MatrixXd ConsiderCovariance::AgainstConsider(const double* a) const {
  if (const auto known = against_.find(a); known != against_.end()) return known->second;
  Eigen::MatrixXd out(problem_->ParameterBlockTangentSize(a), num_consider_);
  int column = 0;
  for (const Coordinates& c : consider_) {
    const Eigen::MatrixXd block = Raw(a, c.block);
    for (int i : c.tangent) out.col(column++) = block.col(i);
  }
  return out;
}

Eigen::MatrixXd ConsiderCovariance::Block(const double* a, const double* b) const {
  if (num_consider_ == 0) return Raw(a, b);
  return Raw(a, b) - AgainstConsider(a) * inverse_cc_ * AgainstConsider(b).transpose();
}

Eigen::MatrixXd ConsiderCovariance::Sensitivity(const double* a) const {
  return -AgainstConsider(a) * inverse_cc_;
}

Eigen::MatrixXd ConsiderCovariance::Consider(const double* a, double variance_factor) const {
  const int n = problem_->ParameterBlockTangentSize(a);
  if (num_posterior_ == 0) return Eigen::MatrixXd::Zero(n, n);
  const Eigen::MatrixXd G = Sensitivity(a).leftCols(num_posterior_);
  return G * Posterior(variance_factor) * G.transpose();
}

Eigen::MatrixXd ConsiderCovariance::Independent(const double* a, const double* b) const {
  const int independent = num_consider_ - num_posterior_;
  if (independent == 0)
    return Eigen::MatrixXd::Zero(problem_->ParameterBlockTangentSize(a),
                                 problem_->ParameterBlockTangentSize(b));
  return Sensitivity(a).rightCols(independent) * independent_sigma_ *
         Sensitivity(b).rightCols(independent).transpose();
}

Eigen::VectorXd ConsiderCovariance::Shift(const double* a, double variance_factor) const {
  const int n = problem_->ParameterBlockTangentSize(a);
  if (num_posterior_ == 0) return Eigen::VectorXd::Zero(n);
  return Sensitivity(a).leftCols(num_posterior_) * DeltaC(variance_factor);
}

Eigen::VectorXd ConsiderCovariance::DeltaC(double variance_factor) const {
  return -Posterior(variance_factor) * gradient_ / variance_factor;
}

std::vector<std::pair<int, int>> ConsiderCovariance::HeldAt(const double* block) const {
  std::vector<std::pair<int, int>> held;
  int at = 0;
  for (size_t b = 0; b < posterior_blocks_; ++b)
    for (int i : consider_[b].tangent) {
      if (consider_[b].block == block) held.emplace_back(i, at);
      ++at;
    }
  return held;
}

Eigen::MatrixXd ConsiderCovariance::TangentToAmbient(const double* block) const {
  // A subset manifold's tangent coordinate is one ambient coordinate.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> P =
      Eigen::MatrixXd::Identity(problem_->ParameterBlockSize(block),
                                problem_->ParameterBlockTangentSize(block));
  if (const ceres::Manifold* manifold = problem_->GetManifold(block))
    manifold->PlusJacobian(block, P.data());
  return P;
}

Eigen::VectorXd ConsiderCovariance::Suggested(const double* a, double variance_factor) const {
  Eigen::VectorXd step = Eigen::VectorXd::Zero(problem_->ParameterBlockTangentSize(a));
  if (num_posterior_ > 0) {
    const Eigen::VectorXd delta_c = DeltaC(variance_factor);
    for (const auto& [i, at] : HeldAt(a)) step[i] = delta_c[at];
  }
  return TangentToAmbient(a) * step;
}

Eigen::MatrixXd ConsiderCovariance::ShiftOf(const double* a, const double* block,
                                            double variance_factor) const {
  Eigen::MatrixXd by_tangent = Eigen::MatrixXd::Zero(problem_->ParameterBlockTangentSize(a),
                                                     problem_->ParameterBlockTangentSize(block));
  if (num_posterior_ > 0) {
    const Eigen::MatrixXd G = Sensitivity(a).leftCols(num_posterior_);
    const Eigen::VectorXd delta_c = DeltaC(variance_factor);
    for (const auto& [i, at] : HeldAt(block)) by_tangent.col(i) = G.col(at) * delta_c[at];
  }
  return by_tangent * TangentToAmbient(block).transpose();
}

std::vector<int> ConsiderCovariance::Held(const double* block) const {
  for (size_t b = 0; b < posterior_blocks_; ++b)
    if (consider_[b].block == block) return consider_[b].tangent;
  return {};
}

}  // namespace handeye::internal
