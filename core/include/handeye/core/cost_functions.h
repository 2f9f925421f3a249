// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Ceres cost functors of the joint solve (see calibration.h for X, M, Z).
///
/// One residual block per view: the chain of transforms is composed once per
/// block and then applied to every point of the view, which is several times
/// cheaper under autodiff than a block per point. The robust loss stays per
/// point: with a Cauchy scale a > 0 each point's residual r is returned as
/// r · sqrt(ρ(s)/s), s = ‖r‖², ρ(s) = a² log(1 + s/a²), so the sum of squares
/// of the block is Σ ρ(s_i) — the paper's per-point Cauchy cost, whose minimum
/// this problem shares.

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <vector>

#include "handeye/core/camera.h"
#include "handeye/core/transform.h"

namespace handeye {

/// Detected points of one view: target points and their pixels.
struct ViewPoints {
  std::vector<Eigen::Vector3d> p_target;
  std::vector<Eigen::Vector2d> observed_px;
};

namespace cost_internal {

/// Composes two `[qx qy qz qw tx ty tz]` poses: out = a · b.
template <typename T>
void Compose(const T* a, const T* b, T* out) {
  const Eigen::Map<const Eigen::Quaternion<T>> qa(a), qb(b);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> ta(a + 4), tb(b + 4);
  Eigen::Map<Eigen::Quaternion<T>> q(out);
  Eigen::Map<Eigen::Matrix<T, 3, 1>> t(out + 4);
  const Eigen::Matrix<T, 3, 1> t_new = qa * tb + ta;
  q = qa * qb;
  t = t_new;
}

/// Residual of point i through T_cam_target (a pose block), robustified.
template <typename T>
bool ProjectPoint(const std::array<double, OpenCVCameraModel::kNumParams>& intrinsics, const ViewPoints& view,
                  size_t i, double cauchy_scale_px, const T* T_cam_target, T* residual) {
  T params[OpenCVCameraModel::kNumParams];
  for (int k = 0; k < OpenCVCameraModel::kNumParams; ++k) params[k] = T(intrinsics[k]);
  const T p[3] = {T(view.p_target[i].x()), T(view.p_target[i].y()), T(view.p_target[i].z())};
  T p_cam[3], uv[2];
  TransformPoint(T_cam_target, p, p_cam);
  if (!OpenCVCameraModel::Project(params, p_cam, uv)) return false;
  T r0 = uv[0] - T(view.observed_px[i].x());
  T r1 = uv[1] - T(view.observed_px[i].y());
  if (cauchy_scale_px > 0) {
    // g(x) = sqrt(log1p(x) / x), x = s / a²; its series near 0 keeps jets finite.
    using std::log1p;
    using std::sqrt;
    const T x = (r0 * r0 + r1 * r1) / T(cauchy_scale_px * cauchy_scale_px);
    const T ratio = x < T(1e-8) ? T(1.0) - x / T(2.0) + x * x / T(3.0) : log1p(x) / x;
    const T g = sqrt(ratio);
    r0 *= g;
    r1 *= g;
  }
  residual[0] = r0;
  residual[1] = r1;
  return true;
}

/// Residuals of every point of the view through T_cam_target.
template <typename T>
bool ProjectView(const std::array<double, OpenCVCameraModel::kNumParams>& intrinsics, const ViewPoints& view,
                 double cauchy_scale_px, const T* T_cam_target, T* residuals) {
  for (size_t i = 0; i < view.p_target.size(); ++i)
    if (!ProjectPoint(intrinsics, view, i, cauchy_scale_px, T_cam_target, residuals + 2 * i)) return false;
  return true;
}

/// A view's cost with derivatives by the chain rule: the composed pose
/// T_cam_target = Chain(blocks) is differentiated once per view (jets over
/// all 7·kBlocks parameters), each point only with respect to the 7
/// parameters of that pose. Autodiff over all parameters at every point gives
/// the same numbers several times slower. `Chain` has a templated
/// `void operator()(const T* const* blocks, T* T_cam_target) const`.
template <int kBlocks, typename Chain>
class ChainedViewCost : public ceres::CostFunction {
 public:
  ChainedViewCost(const Camera& camera, ViewPoints points, double cauchy_scale_px, Chain chain)
      : intrinsics_(camera.params), view_(std::move(points)), cauchy_scale_px_(cauchy_scale_px), chain_(chain) {
    set_num_residuals(2 * static_cast<int>(view_.p_target.size()));
    for (int b = 0; b < kBlocks; ++b) mutable_parameter_block_sizes()->push_back(7);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    if (!jacobians) {
      double pose[7];
      chain_(parameters, pose);
      return ProjectView(intrinsics_, view_, cauchy_scale_px_, pose, residuals);
    }
    using JetAll = ceres::Jet<double, 7 * kBlocks>;
    using JetPose = ceres::Jet<double, 7>;
    JetAll blocks[kBlocks][7];
    const JetAll* block_ptrs[kBlocks];
    for (int b = 0; b < kBlocks; ++b) {
      for (int k = 0; k < 7; ++k) blocks[b][k] = JetAll(parameters[b][k], 7 * b + k);
      block_ptrs[b] = blocks[b];
    }
    JetAll pose[7];
    chain_(block_ptrs, pose);
    JetPose pose7[7];
    for (int k = 0; k < 7; ++k) pose7[k] = JetPose(pose[k].a, k);
    for (size_t i = 0; i < view_.p_target.size(); ++i) {
      JetPose r[2];
      if (!ProjectPoint(intrinsics_, view_, i, cauchy_scale_px_, pose7, r)) return false;
      for (int row = 0; row < 2; ++row) {
        residuals[2 * i + row] = r[row].a;
        for (int b = 0; b < kBlocks; ++b) {
          if (!jacobians[b]) continue;
          double* out = jacobians[b] + (2 * i + row) * 7;
          for (int col = 0; col < 7; ++col) {
            double sum = 0;
            for (int k = 0; k < 7; ++k) sum += r[row].v[k] * pose[k].v[7 * b + col];
            out[col] = sum;
          }
        }
      }
    }
    return true;
  }

 private:
  std::array<double, OpenCVCameraModel::kNumParams> intrinsics_;
  ViewPoints view_;
  double cauchy_scale_px_;
  Chain chain_;
};

/// X · M · Z: blocks X, Z.
struct DirectChain {
  PoseParams M;
  template <typename T>
  void operator()(const T* const* blocks, T* out) const {
    T M_t[7], MZ[7];
    for (int i = 0; i < 7; ++i) M_t[i] = T(M[i]);
    Compose(M_t, blocks[1], MZ);
    Compose(blocks[0], MZ, out);
  }
};

/// T_camk_camt · X_t · M · Z: blocks T_camk_camt, X_t, Z.
struct CrossChain {
  PoseParams M;
  template <typename T>
  void operator()(const T* const* blocks, T* out) const {
    T XMZ[7];
    const T* direct[2] = {blocks[1], blocks[2]};
    DirectChain{M}(direct, XMZ);
    Compose(blocks[0], XMZ, out);
  }
};

}  // namespace cost_internal

/// c_rpj of one view: every point against X_k · M_j · Z · p_target.
/// Parameters: X_k and Z as `[qx qy qz qw tx ty tz]`. Residuals: 2 per point (pixels).
struct ViewReprojectionError {
  ViewReprojectionError(const Camera& camera, const Eigen::Isometry3d& M, ViewPoints points,
                        double cauchy_scale_px)
      : intrinsics(camera.params), M(ToPoseParams(M)), view(std::move(points)), cauchy_scale_px(cauchy_scale_px) {}

  template <typename T>
  bool operator()(const T* X, const T* Z, T* residuals) const {
    const T* blocks[2] = {X, Z};
    T pose[7];
    cost_internal::DirectChain{M}(blocks, pose);
    return cost_internal::ProjectView(intrinsics, view, cauchy_scale_px, pose, residuals);
  }

  /// The cost with chain-rule derivatives (same values as autodiff of
  /// operator(), faster). `cauchy_scale_px` <= 0: plain squared error.
  static ceres::CostFunction* Create(const Camera& camera, const Eigen::Isometry3d& M, ViewPoints points,
                                     double cauchy_scale_px) {
    return new cost_internal::ChainedViewCost<2, cost_internal::DirectChain>(
        camera, std::move(points), cauchy_scale_px, cost_internal::DirectChain{ToPoseParams(M)});
  }
  /// The same cost through ceres::AutoDiffCostFunction (reference for tests).
  static ceres::CostFunction* CreateAutoDiff(const Camera& camera, const Eigen::Isometry3d& M, ViewPoints points,
                                             double cauchy_scale_px) {
    const int residuals = 2 * static_cast<int>(points.p_target.size());
    return new ceres::AutoDiffCostFunction<ViewReprojectionError, ceres::DYNAMIC, 7, 7>(
        new ViewReprojectionError(camera, M, std::move(points), cauchy_scale_px), residuals);
  }

  std::array<double, OpenCVCameraModel::kNumParams> intrinsics;
  PoseParams M;
  ViewPoints view;
  double cauchy_scale_px;
};

/// c_cross of one view of camera k at pose j, predicted through camera t:
/// T_camk_camt · X_t · M_j · Z · p_target. Parameters: T_camk_camt, X_t, Z.
struct ViewCrossReprojectionError {
  ViewCrossReprojectionError(const Camera& camera_k, const Eigen::Isometry3d& M, ViewPoints points,
                             double cauchy_scale_px)
      : direct(camera_k, M, std::move(points), cauchy_scale_px) {}

  template <typename T>
  bool operator()(const T* T_camk_camt, const T* X_t, const T* Z, T* residuals) const {
    const T* blocks[3] = {T_camk_camt, X_t, Z};
    T pose[7];
    cost_internal::CrossChain{direct.M}(blocks, pose);
    return cost_internal::ProjectView(direct.intrinsics, direct.view, direct.cauchy_scale_px, pose, residuals);
  }

  /// The cost with chain-rule derivatives (see ViewReprojectionError::Create).
  static ceres::CostFunction* Create(const Camera& camera_k, const Eigen::Isometry3d& M, ViewPoints points,
                                     double cauchy_scale_px) {
    return new cost_internal::ChainedViewCost<3, cost_internal::CrossChain>(
        camera_k, std::move(points), cauchy_scale_px, cost_internal::CrossChain{ToPoseParams(M)});
  }
  /// The same cost through ceres::AutoDiffCostFunction (reference for tests).
  static ceres::CostFunction* CreateAutoDiff(const Camera& camera_k, const Eigen::Isometry3d& M, ViewPoints points,
                                             double cauchy_scale_px) {
    const int residuals = 2 * static_cast<int>(points.p_target.size());
    return new ceres::AutoDiffCostFunction<ViewCrossReprojectionError, ceres::DYNAMIC, 7, 7, 7>(
        new ViewCrossReprojectionError(camera_k, M, std::move(points), cauchy_scale_px), residuals);
  }

  ViewReprojectionError direct;
};

}  // namespace handeye
