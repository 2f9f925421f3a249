// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The one place in core that computes covariances of the chain's parameter
// blocks (ceres::Covariance): the joint solve's sigma, the intrinsics check,
// the drift check and the noise-only bound all read theirs from here
// (tests/CMakeLists.txt checks with nm that no other object uses
// ceres::Covariance), and the factor that scales them to the residuals seen.

#include <ceres/covariance.h>
#include <ceres/problem.h>

#include <Eigen/Core>
#include <memory>
#include <utility>
#include <vector>

namespace handeye::internal {

/// Covariance blocks of a solved problem at its current values (the inverse
/// of JᵀJ, not scaled by the residuals: callers scale by their variance
/// factor).
class BlockCovariance {
 public:
  using Pairs = std::vector<std::pair<const double*, const double*>>;
  /// Computes the blocks `pairs` of `problem` (which must outlive this) with
  /// `algorithm`: DENSE_SVD for small problems, SPARSE_QR for those with a
  /// block per robot pose.
  BlockCovariance(ceres::Problem* problem, const Pairs& pairs,
                  ceres::CovarianceAlgorithmType algorithm, int threads = 1);
  ~BlockCovariance();
  /// False when the Jacobian is rank deficient: no block is available then.
  bool ok() const { return ok_; }
  /// The block of (a, b) in their tangent spaces (rows: a's, columns: b's).
  Eigen::MatrixXd Tangent(const double* a, const double* b) const;
  /// The block of (a, b) in their parameters.
  Eigen::MatrixXd Ambient(const double* a, const double* b) const;

 private:
  ceres::Problem* problem_;
  std::unique_ptr<ceres::Covariance> covariance_;
  bool ok_ = false;
};

/// The factor that turns a covariance from Ceres (unit residuals) into one
/// of the residuals actually seen: the a posteriori variance factor (2·cost
/// over residuals minus free parameters) times the view design factor, how
/// much an error shared by the points of a view (a robot pose error not
/// modelled, a view's blur) inflates the variance: 1 for independent points,
/// up to the points per view when all move together (from the view blocks'
/// residuals).
double VarianceFactor(ceres::Problem* problem, const std::vector<ceres::ResidualBlockId>& views);

/// The t beyond which Student's t distribution with `dof` (> 0) degrees of
/// freedom leaves the upper tail `tail` (0 < tail < 0.5): what a difference
/// over its σ must exceed where σ² was estimated from `dof` degrees of
/// freedom (a variance factor, a variance component).
double StudentUpperQuantile(double tail, double dof);

}  // namespace handeye::internal
