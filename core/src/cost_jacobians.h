// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The hand-derived derivatives behind the cost functions' Create()
// (handeye/core/cost_functions.h): of pose composition, of the per-point
// Cauchy scaling, of a projection with the intrinsics as unknowns, and the
// view cost that chains them. tests/core/cost_jacobians_test.cc checks each
// against autodiff.
//
// The chains are written in the paper's letters, which keep the derivative
// names short (d_MZ_d_Z): X = T_cam_mount, M = T_mount_holder, Z =
// T_holder_target (handeye/core/setup_frames.h), so X · M · Z = T_cam_target.

#include <ceres/cost_function.h>
#include <ceres/jet.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <memory>

#include "handeye/core/camera.h"
#include "cost_functions.h"
#include "handeye/core/transform.h"

namespace handeye::cost_internal {

using Matrix7 = Eigen::Matrix<double, 7, 7>;

/// [v]×, the matrix of the cross product v × ·.
inline Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return S;
}

/// d(q·v)/d[qx qy qz qw] (3×4) of Eigen's rotation formula
/// q·v = v + 2w(u×v) + 2u×(u×v), u = (qx, qy, qz), w = qw. Taken off the
/// unit sphere too (Ceres wants the derivative in all 7 block coordinates),
/// so it matches autodiff of the same formula, not of R(q/|q|)·v. Linear in v.
inline Eigen::Matrix<double, 3, 4> RotateJacobianQ(const double* q, const Eigen::Vector3d& v) {
  const Eigen::Vector3d u(q[0], q[1], q[2]);
  const double w = q[3];
  Eigen::Matrix<double, 3, 4> J;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  J.leftCols<3>() = -2.0 * w * Skew(v) + 2.0 * (u * v.transpose() + u.dot(v) * I - 2.0 * v * u.transpose());
  J.col(3) = 2.0 * u.cross(v);
  return J;
}

/// d(q·v)/dv (3×3) of the same formula: I + 2w[u]× + 2[u]×².
inline Eigen::Matrix3d RotateJacobianV(const double* q) {
  const Eigen::Matrix3d S = Skew(Eigen::Vector3d(q[0], q[1], q[2]));
  return Eigen::Matrix3d::Identity() + 2.0 * q[3] * S + 2.0 * S * S;
}

/// Derivatives of Compose(a, b) with respect to a and b (7×7 each; either may be null).
inline void ComposeJacobians(const double* a, const double* b, Matrix7* d_a, Matrix7* d_b) {
  const Eigen::Vector3d ua(a[0], a[1], a[2]), ub(b[0], b[1], b[2]);
  const double wa = a[3], wb = b[3];
  // qa·qb = (wa·ub + wb·ua + ua×ub, wa·wb − ua·ub) in [x y z w] order.
  if (d_a) {
    d_a->setZero();
    d_a->block<3, 3>(0, 0) = wb * Eigen::Matrix3d::Identity() - Skew(ub);
    d_a->block<3, 1>(0, 3) = ub;
    d_a->block<1, 3>(3, 0) = -ub.transpose();
    (*d_a)(3, 3) = wb;
    d_a->block<3, 4>(4, 0) = RotateJacobianQ(a, Eigen::Vector3d(b[4], b[5], b[6]));
    d_a->block<3, 3>(4, 4) = Eigen::Matrix3d::Identity();
  }
  if (d_b) {
    d_b->setZero();
    d_b->block<3, 3>(0, 0) = wa * Eigen::Matrix3d::Identity() + Skew(ua);
    d_b->block<3, 1>(0, 3) = ua;
    d_b->block<1, 3>(3, 0) = -ua.transpose();
    (*d_b)(3, 3) = wa;
    d_b->block<3, 3>(4, 4) = RotateJacobianV(a);
  }
}

/// The per-point Cauchy scaling of ProjectPoint applied to a residual r in
/// place, with its derivative d(out)/dr; identity when `cauchy_scale_px` <= 0.
inline Eigen::Matrix2d ApplyCauchy(double cauchy_scale_px, Eigen::Vector2d* r) {
  if (!(cauchy_scale_px > 0)) return Eigen::Matrix2d::Identity();
  // out = g(x)·r, g = sqrt(ratio(x)), ratio = log1p(x)/x, x = |r|²/a²; the
  // same series as ProjectPoint near 0.
  const double a2 = cauchy_scale_px * cauchy_scale_px;
  const double xc = r->squaredNorm() / a2;
  double ratio, d_ratio;
  if (xc < 1e-8) {
    ratio = 1.0 - xc / 2.0 + xc * xc / 3.0;
    d_ratio = -0.5 + 2.0 * xc / 3.0;
  } else {
    ratio = std::log1p(xc) / xc;
    d_ratio = (1.0 / (1.0 + xc) - ratio) / xc;
  }
  const double g = std::sqrt(ratio);
  const double d_g = d_ratio / (2.0 * g);  // dg/dx
  // d(g·r)/dr = g·I + r · (dg/dx · 2 rᵀ / a²)
  const Eigen::Matrix2d d_out_d_r = g * Eigen::Matrix2d::Identity() + (2.0 * d_g / a2) * (*r) * r->transpose();
  *r *= g;
  return d_out_d_r;
}

/// The intrinsics as constant jets over the two normalised coordinates.
using IntrinsicsJet2 = std::array<ceres::Jet<double, 2>, OpenCVCameraModel::kNumParams>;

/// ProjectPoint's residual of one point given in the camera frame, with its
/// derivative with respect to that point (2×3): the camera model's
/// ProjectWithJacobian, then the Cauchy scaling by hand. It runs once per
/// point and view of every Jacobian evaluation of the joint solve.
inline bool ProjectPointWithJacobian(const IntrinsicsJet2& intrinsics, const double* p_cam,
                                     const Eigen::Vector2d& observed_px, double cauchy_scale_px,
                                     double* residual, Eigen::Matrix<double, 2, 3>* d_residual_d_p_cam) {
  double uv[2];
  Eigen::Matrix<double, 2, 3> d_uv_d_p;
  if (!OpenCVCameraModel::ProjectWithJacobian(intrinsics.data(), p_cam, uv, &d_uv_d_p)) return false;
  Eigen::Vector2d r(uv[0] - observed_px.x(), uv[1] - observed_px.y());
  const Eigen::Matrix2d d_out_d_r = ApplyCauchy(cauchy_scale_px, &r);
  residual[0] = r.x();
  residual[1] = r.y();
  d_residual_d_p_cam->noalias() = d_out_d_r * d_uv_d_p;
  return true;
}

/// Derivative of a residual with respect to the 18 intrinsics.
using IntrinsicsJacobian = OpenCVCameraModel::IntrinsicsJacobian;

/// The same with the intrinsics as unknowns: also d(residual)/d(intrinsics),
/// the camera model's ProjectWithIntrinsicsJacobian, then the Cauchy scaling.
inline bool ProjectPointWithIntrinsicsJacobian(const double* intrinsics, const double* p_cam,
                                               const Eigen::Vector2d& observed_px, double cauchy_scale_px,
                                               double* residual, Eigen::Matrix<double, 2, 3>* d_residual_d_p_cam,
                                               IntrinsicsJacobian* d_residual_d_intrinsics) {
  using Jet = ceres::Jet<double, 2 + OpenCVCameraModel::kNumDistortion>;
  double uv[2];
  Eigen::Matrix<double, 2, 3> d_uv_d_p;
  IntrinsicsJacobian d_uv_d_k;
  if (!OpenCVCameraModel::ProjectWithIntrinsicsJacobian<Jet>(intrinsics, p_cam, uv, &d_uv_d_p, &d_uv_d_k))
    return false;
  Eigen::Vector2d r(uv[0] - observed_px.x(), uv[1] - observed_px.y());
  const Eigen::Matrix2d d_out_d_r = ApplyCauchy(cauchy_scale_px, &r);
  residual[0] = r.x();
  residual[1] = r.y();
  d_residual_d_p_cam->noalias() = d_out_d_r * d_uv_d_p;
  d_residual_d_intrinsics->noalias() = d_out_d_r * d_uv_d_k;
  return true;
}

/// X · M · Z: blocks X, Z.
struct DirectChainJacobian : DirectChain {
  /// The same pose and its derivative with respect to (X, Z).
  void Jacobian(const double* const* blocks, double* out, Eigen::Matrix<double, 7, 14>* d_out) const {
    double MZ[7];
    Compose(M.data(), blocks[1], MZ);
    Compose(blocks[0], MZ, out);
    Matrix7 d_MZ_d_Z, d_out_d_X, d_out_d_MZ;
    ComposeJacobians(M.data(), blocks[1], nullptr, &d_MZ_d_Z);
    ComposeJacobians(blocks[0], MZ, &d_out_d_X, &d_out_d_MZ);
    d_out->leftCols<7>() = d_out_d_X;
    d_out->rightCols<7>().noalias() = d_out_d_MZ * d_MZ_d_Z;
  }
};

/// T_camk_camt · X_t · M · Z: blocks T_camk_camt, X_t, Z.
struct CrossChainJacobian : CrossChain {
  /// The same pose and its derivative with respect to (T_camk_camt, X_t, Z).
  void Jacobian(const double* const* blocks, double* out, Eigen::Matrix<double, 7, 21>* d_out) const {
    double XMZ[7];
    Eigen::Matrix<double, 7, 14> d_XMZ;
    const double* direct[2] = {blocks[1], blocks[2]};
    DirectChainJacobian{{M}}.Jacobian(direct, XMZ, &d_XMZ);
    Compose(blocks[0], XMZ, out);
    Matrix7 d_out_d_T, d_out_d_XMZ;
    ComposeJacobians(blocks[0], XMZ, &d_out_d_T, &d_out_d_XMZ);
    d_out->leftCols<7>() = d_out_d_T;
    d_out->rightCols<14>().noalias() = d_out_d_XMZ * d_XMZ;
  }
};

/// X · M · Z with the robot pose M a block too: blocks X, M, Z (the joint
/// solve with robot pose corrections; X may be a pair's Y_kt).
struct RobotChainJacobian : RobotChain {
  /// The same pose and its derivative with respect to (X, M, Z).
  void Jacobian(const double* const* blocks, double* out, Eigen::Matrix<double, 7, 21>* d_out) const {
    double MZ[7];
    Compose(blocks[1], blocks[2], MZ);
    Compose(blocks[0], MZ, out);
    Matrix7 d_MZ_d_M, d_MZ_d_Z, d_out_d_X, d_out_d_MZ;
    ComposeJacobians(blocks[1], blocks[2], &d_MZ_d_M, &d_MZ_d_Z);
    ComposeJacobians(blocks[0], MZ, &d_out_d_X, &d_out_d_MZ);
    d_out->leftCols<7>() = d_out_d_X;
    d_out->middleCols<7>(7).noalias() = d_out_d_MZ * d_MZ_d_M;
    d_out->rightCols<7>().noalias() = d_out_d_MZ * d_MZ_d_Z;
  }
};

/// A view's cost with derivatives by the chain rule. The composed pose
/// T_cam_target = Chain(blocks) and its 7×(7·kBlocks) derivative D are
/// computed once per view (closed form, see ComposeJacobians); since
/// p_cam = q·p + t is linear in the target point p, its derivative with
/// respect to every parameter is Σ_m p_m·H_m + H_t with four 3×(7·kBlocks)
/// matrices per view. Each point then costs its projection, a 2×3 derivative
/// and two small products. Autodiff over all parameters at every point gives
/// the same numbers many times slower. `Chain` has a templated
/// `void operator()(const T* const* blocks, T* T_cam_target) const` and
/// `void Jacobian(const double* const* blocks, double* T_cam_target,
/// Eigen::Matrix<double, 7, 7 * kBlocks>* d) const`.
/// With `free_intrinsics`, the camera's 18 intrinsics are one more parameter
/// block (the last), in OpenCVCameraModel order.
/// The view's points are shared, not copied: the joint solve makes one block
/// per camera pair for each view.
template <int kBlocks, typename Chain>
class ChainedViewCost : public ceres::CostFunction {
 public:
  ChainedViewCost(const Camera& camera, std::shared_ptr<const ViewPoints> points, double cauchy_scale_px,
                  Chain chain, bool free_intrinsics = false)
      : intrinsics_(camera.params), view_(std::move(points)), cauchy_scale_px_(cauchy_scale_px), chain_(chain),
        free_intrinsics_(free_intrinsics) {
    for (int k = 0; k < OpenCVCameraModel::kNumParams; ++k)
      intrinsics_jet_[k] = ceres::Jet<double, 2>(intrinsics_[k]);
    set_num_residuals(2 * static_cast<int>(view_->p_target.size()));
    for (int b = 0; b < kBlocks; ++b) mutable_parameter_block_sizes()->push_back(7);
    if (free_intrinsics_) mutable_parameter_block_sizes()->push_back(OpenCVCameraModel::kNumParams);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* intrinsics = free_intrinsics_ ? parameters[kBlocks] : intrinsics_.data();
    if (!jacobians) {
      double pose[7];
      chain_(parameters, pose);
      return ProjectView(intrinsics, *view_, cauchy_scale_px_, pose, residuals);
    }
    constexpr int kParams = 7 * kBlocks;
    using Jacobian3 = Eigen::Matrix<double, 3, kParams>;
    double pose[7];
    Eigen::Matrix<double, 7, kParams> d_pose;
    chain_.Jacobian(parameters, pose, &d_pose);
    // H_m = d(q·e_m)/dq · dq/d(parameters); H_t = dt/d(parameters).
    Jacobian3 H[3];
    for (int m = 0; m < 3; ++m)
      H[m].noalias() = RotateJacobianQ(pose, Eigen::Vector3d::Unit(m)) * d_pose.template topRows<4>();
    const Jacobian3 H_t = d_pose.template bottomRows<3>();

    using RowMajor2x7 = Eigen::Matrix<double, 2, 7, Eigen::RowMajor>;
    double* d_intrinsics = free_intrinsics_ ? jacobians[kBlocks] : nullptr;
    for (size_t i = 0; i < view_->p_target.size(); ++i) {
      const Eigen::Vector3d& p = view_->p_target[i];
      double p_cam[3];
      TransformPoint(pose, p.data(), p_cam);
      Eigen::Matrix<double, 2, 3> d_r_d_p;
      if (free_intrinsics_) {
        IntrinsicsJacobian d_r_d_k;
        if (!ProjectPointWithIntrinsicsJacobian(intrinsics, p_cam, view_->observed_px[i], cauchy_scale_px_,
                                                residuals + 2 * i, &d_r_d_p, &d_r_d_k))
          return false;
        if (d_intrinsics)
          Eigen::Map<IntrinsicsJacobian>(d_intrinsics + 2 * OpenCVCameraModel::kNumParams * i) = d_r_d_k;
      } else if (!ProjectPointWithJacobian(intrinsics_jet_, p_cam, view_->observed_px[i], cauchy_scale_px_,
                                           residuals + 2 * i, &d_r_d_p)) {
        return false;
      }
      Jacobian3 d_p_d_params = H_t;
      d_p_d_params.noalias() += p.x() * H[0] + p.y() * H[1] + p.z() * H[2];
      const Eigen::Matrix<double, 2, kParams> J = d_r_d_p * d_p_d_params;
      for (int b = 0; b < kBlocks; ++b)
        if (jacobians[b]) Eigen::Map<RowMajor2x7>(jacobians[b] + 14 * i) = J.template middleCols<7>(7 * b);
    }
    return true;
  }

 private:
  std::array<double, OpenCVCameraModel::kNumParams> intrinsics_;
  IntrinsicsJet2 intrinsics_jet_;
  std::shared_ptr<const ViewPoints> view_;
  double cauchy_scale_px_;
  Chain chain_;
  bool free_intrinsics_;
};

}  // namespace handeye::cost_internal
