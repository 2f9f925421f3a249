// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Ceres cost functors of the joint solve, over the chain (calibration.h)
/// T_cam_target = T_cam_mount · T_mount_holder · T_holder_target, the paper's
/// X · M · Z (the letters stay in the chain functors' short local names):
/// their templated operator() is the reference (autodiff), their Create()
/// the cost the solver uses, with derivatives by hand (core/src/cost_jacobians.h).
///
/// One residual block per view: the chain of transforms is composed once per
/// block and then applied to every point of the view, which is several times
/// cheaper under autodiff than a block per point. The robust loss stays per
/// point: with a Cauchy scale a > 0 each point's residual r is returned as
/// r · sqrt(ρ(s)/s), s = ‖r‖², ρ(s) = a² log(1 + s/a²), so the sum of squares
/// of the block is Σ ρ(s_i) — the paper's per-point Cauchy cost, whose minimum
/// this problem shares.

#include <ceres/autodiff_cost_function.h>
#include <ceres/cost_function.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <memory>
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
/// `intrinsics`: OpenCVCameraModel parameters (double, or jets when they are unknowns).
template <typename T, typename U>
bool ProjectPoint(const U* intrinsics, const ViewPoints& view, size_t i, double cauchy_scale_px,
                  const T* T_cam_target, T* residual) {
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
template <typename T, typename U>
bool ProjectView(const U* intrinsics, const ViewPoints& view, double cauchy_scale_px, const T* T_cam_target,
                 T* residuals) {
  for (size_t i = 0; i < view.p_target.size(); ++i)
    if (!ProjectPoint(intrinsics, view, i, cauchy_scale_px, T_cam_target, residuals + 2 * i)) return false;
  return true;
}

/// T_cam_mount · T_mount_holder · T_holder_target (X · M · Z): blocks
/// T_cam_mount, T_holder_target.
struct DirectChain {
  PoseParams M;  ///< T_mount_holder of the view's robot pose
  template <typename T>
  void operator()(const T* const* blocks, T* out) const {
    T M_t[7], MZ[7];
    for (int i = 0; i < 7; ++i) M_t[i] = T(M[i]);
    Compose(M_t, blocks[1], MZ);
    Compose(blocks[0], MZ, out);
  }
};

/// T_camk_camt · T_camt_mount · T_mount_holder · T_holder_target: blocks
/// T_camk_camt, T_camt_mount, T_holder_target.
struct CrossChain {
  PoseParams M;  ///< T_mount_holder of the view's robot pose
  template <typename T>
  void operator()(const T* const* blocks, T* out) const {
    T XMZ[7];
    const T* direct[2] = {blocks[1], blocks[2]};
    DirectChain{M}(direct, XMZ);
    Compose(blocks[0], XMZ, out);
  }
};

/// T_cam_mount · T_mount_holder · T_holder_target with the robot pose a block
/// too: blocks T_cam_mount, T_mount_holder, T_holder_target (the joint solve
/// with robot pose corrections; T_cam_mount may be a pair's T_camk_mount_via_t).
struct RobotChain {
  template <typename T>
  void operator()(const T* const* blocks, T* out) const {
    T MZ[7];
    Compose(blocks[1], blocks[2], MZ);
    Compose(blocks[0], MZ, out);
  }
};

}  // namespace cost_internal

/// c_rpj of one view with the robot pose as a parameter block:
/// T_cam_mount · T_mount_holder[j] · T_holder_target. Parameters T_cam_mount
/// (or a pair's T_camk_mount_via_t, see RefineJoint), T_mount_holder[j],
/// T_holder_target. Residuals: 2 per point (pixels).
struct ViewReprojectionWithRobotError {
  /// With `free_intrinsics`, a fourth block: the camera's 18 intrinsics.
  static ceres::CostFunction* Create(const Camera& camera, std::shared_ptr<const ViewPoints> points,
                                     double cauchy_scale_px, bool free_intrinsics = false);
  template <typename T>
  bool operator()(const T* T_cam_mount, const T* T_mount_holder, const T* T_holder_target, T* residuals) const {
    const T* blocks[3] = {T_cam_mount, T_mount_holder, T_holder_target};
    T pose[7];
    cost_internal::RobotChain{}(blocks, pose);
    return cost_internal::ProjectView(intrinsics.data(), view, cauchy_scale_px, pose, residuals);
  }
  std::array<double, OpenCVCameraModel::kNumParams> intrinsics;
  ViewPoints view;
  double cauchy_scale_px;
};

/// The prior of a robot pose: how far the solved T_base_ee may be from the
/// reported one. Parameter: T_mount_holder (`[qx qy qz qw tx ty tz]`), which
/// is T_base_ee (eye_to_hand) or its inverse (eye_in_hand; `inverse`, see
/// SetupFrames::RobotPoseInverted). Residuals (6): the rotation
/// R_base_ee · R_reported⁻¹ as a rotation vector over `sigma_rad` (per axis,
/// about the flange, in the base frame) and the flange's displacement over
/// `sigma_m` (per axis), both times `pixel_sigma_px`, so that the prior
/// and the pixel residuals are weighted by their noise alike.
struct RobotPosePrior {
  template <typename T>
  bool operator()(const T* T_mount_holder, T* residuals) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(T_mount_holder);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(T_mount_holder + 4);
    Eigen::Quaternion<T> q_base_ee = q;
    Eigen::Matrix<T, 3, 1> t_base_ee = t;
    if (inverse) {
      q_base_ee = q.conjugate();
      t_base_ee = -(q_base_ee * t);
    }
    const Eigen::Quaternion<T> q_reported(T(reported.w()), T(reported.x()), T(reported.y()), T(reported.z()));
    Eigen::Quaternion<T> dq = q_base_ee * q_reported.conjugate();
    if (dq.w() < T(0)) dq.coeffs() = -dq.coeffs();
    // Rotation vector of dq (small angles: 2·xyz is exact to third order).
    const T s = dq.vec().norm();
    const T scale = s > T(1e-12) ? T(2.0) * atan2(s, dq.w()) / s : T(2.0);
    for (int i = 0; i < 3; ++i) {
      residuals[i] = weight_rotation * scale * dq.vec()[i];
      residuals[3 + i] = weight_translation * (t_base_ee[i] - T(t_reported[i]));
    }
    return true;
  }
  static ceres::CostFunction* Create(const Eigen::Isometry3d& T_base_ee_reported, bool inverse, double sigma_rad,
                                     double sigma_m, double pixel_sigma_px) {
    auto* prior = new RobotPosePrior;
    prior->reported = Eigen::Quaterniond(T_base_ee_reported.rotation());
    prior->t_reported = T_base_ee_reported.translation();
    prior->inverse = inverse;
    prior->weight_rotation = pixel_sigma_px / sigma_rad;
    prior->weight_translation = pixel_sigma_px / sigma_m;
    return new ceres::AutoDiffCostFunction<RobotPosePrior, 6, 7>(prior);
  }
  Eigen::Quaterniond reported;
  Eigen::Vector3d t_reported;
  bool inverse = false;
  double weight_rotation = 1, weight_translation = 1;
};

/// c_rpj of one view: every point against T_cam_mount · T_mount_holder[j] ·
/// T_holder_target · p_target. Parameters: T_cam_mount and T_holder_target as
/// `[qx qy qz qw tx ty tz]`. Residuals: 2 per point (pixels).
struct ViewReprojectionError {
  ViewReprojectionError(const Camera& camera, const Eigen::Isometry3d& T_mount_holder, ViewPoints points,
                        double cauchy_scale_px)
      : intrinsics(camera.params),
        M(ToPoseParams(T_mount_holder)),
        view(std::move(points)),
        cauchy_scale_px(cauchy_scale_px) {}

  template <typename T>
  bool operator()(const T* T_cam_mount, const T* T_holder_target, T* residuals) const {
    const T* blocks[2] = {T_cam_mount, T_holder_target};
    T pose[7];
    cost_internal::DirectChain{M}(blocks, pose);
    return cost_internal::ProjectView(intrinsics.data(), view, cauchy_scale_px, pose, residuals);
  }
  /// The same with the intrinsics as a third block (autodiff reference).
  template <typename T>
  bool operator()(const T* T_cam_mount, const T* T_holder_target, const T* K, T* residuals) const {
    const T* blocks[2] = {T_cam_mount, T_holder_target};
    T pose[7];
    cost_internal::DirectChain{M}(blocks, pose);
    return cost_internal::ProjectView(K, view, cauchy_scale_px, pose, residuals);
  }

  /// The cost with chain-rule derivatives (same values as autodiff of
  /// operator(), faster). `cauchy_scale_px` <= 0: plain squared error.
  static ceres::CostFunction* Create(const Camera& camera, const Eigen::Isometry3d& T_mount_holder, ViewPoints points,
                                     double cauchy_scale_px);
  /// The same, sharing the view's points with other blocks (the cross terms of the view).
  /// With `free_intrinsics`, a third block: the camera's 18 intrinsics.
  static ceres::CostFunction* Create(const Camera& camera, const Eigen::Isometry3d& T_mount_holder,
                                     std::shared_ptr<const ViewPoints> points, double cauchy_scale_px,
                                     bool free_intrinsics = false);

  std::array<double, OpenCVCameraModel::kNumParams> intrinsics;
  PoseParams M;  ///< T_mount_holder of the view's robot pose (the paper's M_j)
  ViewPoints view;
  double cauchy_scale_px;
};

/// c_cross of one view of camera k at pose j, predicted through camera t:
/// T_camk_camt · T_camt_mount · T_mount_holder[j] · T_holder_target ·
/// p_target. Parameters: T_camk_camt, T_camt_mount, T_holder_target.
/// The paper's form. Its residuals are those of ViewReprojectionError with
/// T_cam_mount = T_camk_camt · T_camt_mount, and since T_camk_camt is a free
/// block per pair the joint solve uses that form in the variable
/// T_camk_mount_via_t = T_camk_camt · T_camt_mount (two blocks per residual
/// block instead of three; see RefineJoint).
struct ViewCrossReprojectionError {
  ViewCrossReprojectionError(const Camera& camera_k, const Eigen::Isometry3d& T_mount_holder, ViewPoints points,
                             double cauchy_scale_px)
      : direct(camera_k, T_mount_holder, std::move(points), cauchy_scale_px) {}

  template <typename T>
  bool operator()(const T* T_camk_camt, const T* T_camt_mount, const T* T_holder_target, T* residuals) const {
    const T* blocks[3] = {T_camk_camt, T_camt_mount, T_holder_target};
    T pose[7];
    cost_internal::CrossChain{direct.M}(blocks, pose);
    return cost_internal::ProjectView(direct.intrinsics.data(), direct.view, direct.cauchy_scale_px, pose, residuals);
  }

  /// The cost with chain-rule derivatives (see ViewReprojectionError::Create).
  static ceres::CostFunction* Create(const Camera& camera_k, const Eigen::Isometry3d& T_mount_holder, ViewPoints points,
                                     double cauchy_scale_px);

  ViewReprojectionError direct;
};

}  // namespace handeye
