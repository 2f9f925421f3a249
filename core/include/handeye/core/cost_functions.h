// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Ceres cost functors of the joint solve (see calibration.h for X, M, Z).

#include <ceres/autodiff_cost_function.h>

#include <array>

#include "handeye/core/camera.h"
#include "handeye/core/transform.h"

namespace handeye {

/// c_rpj: a detected point against its prediction X_k · M_j · Z · p_target.
/// Parameters: X_k and Z as `[qx qy qz qw tx ty tz]`. Residual: pixels (2).
struct ReprojectionError {
  ReprojectionError(const Camera& camera, const Eigen::Isometry3d& M, const Eigen::Vector3d& p_target,
                    const Eigen::Vector2d& observed_px)
      : intrinsics(camera.params), M(ToPoseParams(M)), p_target(p_target), observed(observed_px) {}

  template <typename T>
  bool operator()(const T* X, const T* Z, T* residual) const {
    T p[3], q[3], p_cam[3];
    const T p_t[3] = {T(p_target.x()), T(p_target.y()), T(p_target.z())};
    TransformPoint(Z, p_t, p);
    T M_t[7];
    for (int i = 0; i < 7; ++i) M_t[i] = T(M[i]);
    TransformPoint(M_t, p, q);
    TransformPoint(X, q, p_cam);
    return Residual(p_cam, residual);
  }

  template <typename T>
  bool Residual(const T* p_cam, T* residual) const {
    T params[OpenCVCameraModel::kNumParams];
    for (int i = 0; i < OpenCVCameraModel::kNumParams; ++i) params[i] = T(intrinsics[i]);
    T uv[2];
    if (!OpenCVCameraModel::Project(params, p_cam, uv)) return false;
    residual[0] = uv[0] - T(observed.x());
    residual[1] = uv[1] - T(observed.y());
    return true;
  }

  static ceres::CostFunction* Create(const Camera& camera, const Eigen::Isometry3d& M,
                                     const Eigen::Vector3d& p_target, const Eigen::Vector2d& observed_px) {
    return new ceres::AutoDiffCostFunction<ReprojectionError, 2, 7, 7>(
        new ReprojectionError(camera, M, p_target, observed_px));
  }

  std::array<double, OpenCVCameraModel::kNumParams> intrinsics;
  PoseParams M;
  Eigen::Vector3d p_target;
  Eigen::Vector2d observed;
};

/// c_cross: a point detected by camera k at pose j, predicted through camera t:
/// T_camk_camt · X_t · M_j · Z · p_target. Parameters: T_camk_camt, X_t, Z.
struct CrossReprojectionError {
  CrossReprojectionError(const Camera& camera_k, const Eigen::Isometry3d& M,
                         const Eigen::Vector3d& p_target, const Eigen::Vector2d& observed_px)
      : reprojection(camera_k, M, p_target, observed_px) {}

  template <typename T>
  bool operator()(const T* T_camk_camt, const T* X_t, const T* Z, T* residual) const {
    T p[3], q[3], p_camt[3], p_camk[3];
    const Eigen::Vector3d& pt = reprojection.p_target;
    const T p_t[3] = {T(pt.x()), T(pt.y()), T(pt.z())};
    TransformPoint(Z, p_t, p);
    T M_t[7];
    for (int i = 0; i < 7; ++i) M_t[i] = T(reprojection.M[i]);
    TransformPoint(M_t, p, q);
    TransformPoint(X_t, q, p_camt);
    TransformPoint(T_camk_camt, p_camt, p_camk);
    return reprojection.Residual(p_camk, residual);
  }

  static ceres::CostFunction* Create(const Camera& camera_k, const Eigen::Isometry3d& M,
                                     const Eigen::Vector3d& p_target, const Eigen::Vector2d& observed_px) {
    return new ceres::AutoDiffCostFunction<CrossReprojectionError, 2, 7, 7, 7>(
        new CrossReprojectionError(camera_k, M, p_target, observed_px));
  }

  ReprojectionError reprojection;
};

}  // namespace handeye
