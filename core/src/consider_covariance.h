// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The covariance of a least-squares estimate that holds some uncertain inputs
// at their given values: "consider parameters" (the given intrinsics of a
// camera: known to about 1 %, not estimated). Their uncertainty is no part of
// the residuals, so the covariance of the solve alone leaves it out.

#include <ceres/problem.h>

#include <Eigen/Core>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "covariance.h"

namespace handeye::internal {

/// Two ways to take an uncertain input c into the covariance of the estimate
/// x: (a) make c an unknown under a Gaussian prior of its σ and report the
/// posterior covariance of x; (b) keep the estimate as it is (c held at its
/// given value) and add what the error of c moves it by, the "consider
/// covariance" Cov(x) = A_xx⁻¹ σ² + G Σ_c Gᵀ, G = A_xx⁻¹ A_xc (x moves by
/// −G δc), with A the information of the solve (JᵀJ).
/// (a) is the covariance of another estimator, one that refines c from the
/// views; the estimate reported holds c, and the views cannot correct an
/// input they were not allowed to move: with a camera of few views, the
/// intrinsics error stays in its pose in full, which (a) would not show. So
/// (b), which changes σ only, never the pose. But Σ_c is not the prior's: the
/// views do say something about c (where they determine the focal length to
/// 0.1 %, a prior of 1 % would make σ of a well-seen camera ten times its
/// error), so Σ_c is what is known of c's error given the views — the
/// posterior covariance Σ_post = (Σ_prior⁻¹ + S/σ²)⁻¹, S the views'
/// information on c with x profiled out — and the posterior mean δc of that
/// error enters as a shift G δc of its own (Shift): error ≈ G (δc δcᵀ + Σ_post) Gᵀ.
///
/// All from one Ceres covariance of the problem with c added as unknowns
/// under a prior of information P (any that makes the whole invertible):
/// its inverse H⁻¹ has H⁻¹_xc = −A_xx⁻¹ A_xc (S + P)⁻¹ and H⁻¹_cc = (S + P)⁻¹, so
///   G = −H⁻¹_xc (H⁻¹_cc)⁻¹,  S = (H⁻¹_cc)⁻¹ − P,
///   A_xx⁻¹ = H⁻¹_xx − H⁻¹_xc (H⁻¹_cc)⁻¹ H⁻¹_cx,
/// and δc = −Σ_post g_c / σ² from the cost's gradient g_c at the solution.
///
/// Inputs of a second kind, each record's own (the robot poses, held as
/// reported where held-out poses chose the exact robot), are held too and
/// add G_r Σ_r G_rᵀ at the σ Σ_r they are given (Independent), not a
/// posterior: each pose's error is seen by its few views only, so its
/// posterior mean would be those views' noise, and Σ_r is already what the
/// views together say of the robot (the modelled solve's estimate).
class ConsiderCovariance {
 public:
  /// Consider coordinates of one parameter block: indices into its tangent space.
  struct Coordinates {
    const double* block;
    std::vector<int> tangent;
  };
  /// `consider`: blocks of the problem (each under a prior) and which of
  /// their tangent coordinates are held inputs; `sigma`: the covariance of
  /// those coordinates stacked in that order (units of the parameters, the
  /// prior's); `prior_information`: P, the information the problem's prior
  /// residual blocks give them (in the problem's units).
  ConsiderCovariance(std::vector<Coordinates> consider, Eigen::MatrixXd sigma, Eigen::MatrixXd prior_information);
  /// Holds `independent` coordinates too (of blocks under a prior of any
  /// weight), their error of covariance `independent_sigma` (stacked in that
  /// order); before Compute.
  void HoldIndependent(const std::vector<Coordinates>& independent, Eigen::MatrixXd independent_sigma);

  /// Computes the blocks of `pairs` (and what the consider coordinates need);
  /// false when the information is rank deficient.
  bool Compute(const std::vector<std::pair<const double*, const double*>>& pairs, ceres::Problem* problem,
               int threads);
  /// [A⁻¹]_ab in tangent space: the covariance of the solve for unit
  /// residuals, the consider coordinates held (their rows and columns 0).
  Eigen::MatrixXd Block(const double* a, const double* b) const;
  /// G Σ_post Gᵀ of block a (tangent space): what the held inputs' error
  /// adds, for residuals of variance `variance_factor` per unit.
  Eigen::MatrixXd Consider(const double* a, double variance_factor) const;
  /// G_r Σ_r G_rᵀ of blocks a against b (tangent space): what the
  /// independent inputs' error adds (0 without them).
  Eigen::MatrixXd Independent(const double* a, const double* b) const;
  /// G δc of block a (tangent space): the held estimate less where it would
  /// be with the inputs at what prior and views together say (−G δc is that
  /// move; only its outer product enters σ).
  Eigen::VectorXd Shift(const double* a, double variance_factor) const;
  /// δc of block a in its ambient coordinates: what prior and views together
  /// say its held inputs are off by (their estimate less the given value; 0
  /// in coordinates not held).
  Eigen::VectorXd Suggested(const double* a, double variance_factor) const;
  /// The part of Shift(a) each held coordinate of `block` makes: a column
  /// per ambient coordinate of `block` (0 where it is not held), so a caller
  /// can take out the shift of some inputs and keep the others'.
  Eigen::MatrixXd ShiftOf(const double* a, const double* block, double variance_factor) const;
  /// The tangent coordinates of `block` held as uncertain inputs (none where it has none).
  std::vector<int> Held(const double* block) const;

 private:
  Eigen::MatrixXd Raw(const double* a, const double* b) const;
  /// Of `block`'s held coordinates, (its tangent index, the stacked consider
  /// index) each.
  std::vector<std::pair<int, int>> HeldAt(const double* block) const;
  /// d(ambient)/d(tangent) of `block` at its value: the identity without a manifold.
  Eigen::MatrixXd TangentToAmbient(const double* block) const;
  /// H⁻¹_ac: the block's rows against every consider coordinate.
  Eigen::MatrixXd AgainstConsider(const double* a) const;
  /// G = −H⁻¹_ac (H⁻¹_cc)⁻¹: how the estimate of block a moves with each
  /// held coordinate (the given intrinsics' first, then the independent ones).
  Eigen::MatrixXd Sensitivity(const double* a) const;

  std::vector<Coordinates> consider_;
  /// Σ_post for residuals of variance `variance_factor`.
  Eigen::MatrixXd Posterior(double variance_factor) const;
  /// δc of every consider coordinate, stacked.
  Eigen::VectorXd DeltaC(double variance_factor) const;

  Eigen::MatrixXd sigma_, prior_information_;
  Eigen::MatrixXd independent_sigma_;  // Σ_r
  Eigen::VectorXd gradient_;  // g_c
  int num_consider_ = 0;       // every held coordinate
  int num_posterior_ = 0;      // of those, the given intrinsics' (the first)
  size_t posterior_blocks_ = 0;  // consider_'s entries of the given intrinsics
  ceres::Problem* problem_ = nullptr;
  std::unique_ptr<BlockCovariance> covariance_;
  Eigen::MatrixXd inverse_cc_;  // (H⁻¹_cc)⁻¹
  /// AgainstConsider of the blocks Compute was given, and of the consider blocks.
  std::map<const double*, Eigen::MatrixXd> against_;
};

}  // namespace handeye::internal
