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

/// Residuals of every point through T_cam_target (a pose block), robustified.
template <typename T>
bool ProjectView(const std::array<double, OpenCVCameraModel::kNumParams>& intrinsics, const ViewPoints& view,
                 double cauchy_scale_px, const T* T_cam_target, T* residuals) {
  T params[OpenCVCameraModel::kNumParams];
  for (int i = 0; i < OpenCVCameraModel::kNumParams; ++i) params[i] = T(intrinsics[i]);
  const double inv_a2 = cauchy_scale_px > 0 ? 1.0 / (cauchy_scale_px * cauchy_scale_px) : 0.0;
  for (size_t i = 0; i < view.p_target.size(); ++i) {
    const T p[3] = {T(view.p_target[i].x()), T(view.p_target[i].y()), T(view.p_target[i].z())};
    T p_cam[3], uv[2];
    TransformPoint(T_cam_target, p, p_cam);
    if (!OpenCVCameraModel::Project(params, p_cam, uv)) return false;
    T r0 = uv[0] - T(view.observed_px[i].x());
    T r1 = uv[1] - T(view.observed_px[i].y());
    if (inv_a2 > 0) {
      // g(x) = sqrt(log1p(x) / x), x = s / a²; its series near 0 keeps jets finite.
      using std::log1p;
      using std::sqrt;
      const T x = (r0 * r0 + r1 * r1) * T(inv_a2);
      const T ratio = x < T(1e-8) ? T(1.0) - x / T(2.0) + x * x / T(3.0) : log1p(x) / x;
      const T g = sqrt(ratio);
      r0 *= g;
      r1 *= g;
    }
    residuals[2 * i] = r0;
    residuals[2 * i + 1] = r1;
  }
  return true;
}

}  // namespace cost_internal

/// c_rpj of one view: every point against X_k · M_j · Z · p_target.
/// Parameters: X_k and Z as `[qx qy qz qw tx ty tz]`. Residuals: 2 per point (pixels).
struct ViewReprojectionError {
  ViewReprojectionError(const Camera& camera, const Eigen::Isometry3d& M, ViewPoints points,
                        double cauchy_scale_px)
      : intrinsics(camera.params), M(ToPoseParams(M)), view(std::move(points)), cauchy_scale_px(cauchy_scale_px) {}

  template <typename T>
  bool operator()(const T* X, const T* Z, T* residuals) const {
    T M_t[7], MZ[7], XMZ[7];
    for (int i = 0; i < 7; ++i) M_t[i] = T(M[i]);
    cost_internal::Compose(M_t, Z, MZ);
    cost_internal::Compose(X, MZ, XMZ);
    return cost_internal::ProjectView(intrinsics, view, cauchy_scale_px, XMZ, residuals);
  }

  /// `cauchy_scale_px` <= 0: plain squared error (no robust loss).
  static ceres::CostFunction* Create(const Camera& camera, const Eigen::Isometry3d& M, ViewPoints points,
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
    T M_t[7], MZ[7], XMZ[7], chain[7];
    for (int i = 0; i < 7; ++i) M_t[i] = T(direct.M[i]);
    cost_internal::Compose(M_t, Z, MZ);
    cost_internal::Compose(X_t, MZ, XMZ);
    cost_internal::Compose(T_camk_camt, XMZ, chain);
    return cost_internal::ProjectView(direct.intrinsics, direct.view, direct.cauchy_scale_px, chain, residuals);
  }

  static ceres::CostFunction* Create(const Camera& camera_k, const Eigen::Isometry3d& M, ViewPoints points,
                                     double cauchy_scale_px) {
    const int residuals = 2 * static_cast<int>(points.p_target.size());
    return new ceres::AutoDiffCostFunction<ViewCrossReprojectionError, ceres::DYNAMIC, 7, 7, 7>(
        new ViewCrossReprojectionError(camera_k, M, std::move(points), cauchy_scale_px), residuals);
  }

  ViewReprojectionError direct;
};

}  // namespace handeye
