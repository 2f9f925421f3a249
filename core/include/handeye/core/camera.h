// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Pinhole camera with OpenCV's distortion model (SPEC §4), usable by Ceres
/// autodiff. Pixels: the centre of the top-left pixel is (0, 0). Camera frame:
/// OpenCV optical frame (x right, y down, z forward).

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace handeye {

/// OpenCV's full model: `fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6 s1 s2 s3 s4 tx ty`.
/// Fewer coefficients (0, 4, 5, 8, 12) are the same model with the rest zero,
/// exactly as `cv::projectPoints` treats them.
struct OpenCVCameraModel {
  static constexpr int kNumParams = 18;
  static constexpr int kNumDistortion = 14;
  static const char* ParamOrder() {
    return "fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6, s1, s2, s3, s4, tau_x, tau_y";
  }

  /// Normalised image point (x, y) = (X/Z, Y/Z) to distorted normalised point,
  /// before the focal length and principal point are applied.
  template <typename T>
  static void Distort(const T* params, const T& x, const T& y, T* xd, T* yd) {
    using std::cos;
    using std::sin;
    const T* k = params + 4;
    const T r2 = x * x + y * y;
    const T r4 = r2 * r2;
    const T r6 = r4 * r2;
    const T radial = (T(1) + k[0] * r2 + k[1] * r4 + k[4] * r6) /
                     (T(1) + k[5] * r2 + k[6] * r4 + k[7] * r6);
    const T xy2 = T(2) * x * y;
    T x0 = x * radial + k[2] * xy2 + k[3] * (r2 + T(2) * x * x) + k[8] * r2 + k[9] * r4;
    T y0 = y * radial + k[2] * (r2 + T(2) * y * y) + k[3] * xy2 + k[10] * r2 + k[11] * r4;
    // Tilted sensor (Scheimpflug): a homography on the distorted point; identity
    // when tau_x = tau_y = 0, skipped then so jets stay cheap.
    if (k[12] != T(0) || k[13] != T(0)) {
      const T ctx = cos(k[12]), stx = sin(k[12]), cty = cos(k[13]), sty = sin(k[13]);
      // R = Ry(tau_y) * Rx(tau_x), as in cv::computeTiltProjectionMatrix.
      const T r00 = cty, r01 = sty * stx, r02 = -sty * ctx;
      const T r10 = T(0), r11 = ctx, r12 = stx;
      const T r20 = sty, r21 = -cty * stx, r22 = cty * ctx;
      // Tilt = [[r22, 0, -r02], [0, r22, -r12], [0, 0, 1]] * R.
      const T h0 = (r22 * r00 - r02 * r20) * x0 + (r22 * r01 - r02 * r21) * y0 + (r22 * r02 - r02 * r22);
      const T h1 = (r22 * r10 - r12 * r20) * x0 + (r22 * r11 - r12 * r21) * y0 + (r22 * r12 - r12 * r22);
      const T h2 = r20 * x0 + r21 * y0 + r22;
      x0 = h0 / h2;
      y0 = h1 / h2;
    }
    *xd = x0;
    *yd = y0;
  }

  /// Projects a point in the camera frame to pixels. Returns false when the
  /// point is not in front of the camera (Z <= 0).
  template <typename T>
  static bool Project(const T* params, const T* p_cam, T* uv) {
    if (!(p_cam[2] > T(0))) return false;
    const T x = p_cam[0] / p_cam[2];
    const T y = p_cam[1] / p_cam[2];
    T xd, yd;
    Distort(params, x, y, &xd, &yd);
    uv[0] = params[0] * xd + params[2];
    uv[1] = params[1] * yd + params[3];
    return true;
  }

  /// Project() with the derivative of the pixel with respect to the point
  /// (2×3), for hand-chained Jacobians (the joint solve's view costs). `params`
  /// are the intrinsics as ceres::Jet<double, 2> with zero derivative parts:
  /// only the distortion goes through jets (over the two normalised
  /// coordinates); the perspective division and the focal length are
  /// differentiated by hand, which keeps the per-point work small.
  template <typename Jet2>
  static bool ProjectWithJacobian(const Jet2* params, const double* p_cam, double* uv,
                                  Eigen::Matrix<double, 2, 3>* d_uv_d_p_cam) {
    if (!(p_cam[2] > 0)) return false;
    const double inv_z = 1.0 / p_cam[2];
    const double x = p_cam[0] / p_cam[2], y = p_cam[1] / p_cam[2];
    Jet2 xd, yd;
    Distort(params, Jet2(x, 0), Jet2(y, 1), &xd, &yd);
    const double fx = params[0].a, fy = params[1].a;
    Eigen::Matrix<double, 2, 2> d_uv_d_xy;  // pixels per normalised coordinate
    d_uv_d_xy << fx * xd.v[0], fx * xd.v[1], fy * yd.v[0], fy * yd.v[1];
    Eigen::Matrix<double, 2, 3> d_xy_d_p;
    d_xy_d_p << inv_z, 0.0, -x * inv_z, 0.0, inv_z, -y * inv_z;
    uv[0] = fx * xd.a + params[2].a;
    uv[1] = fy * yd.a + params[3].a;
    d_uv_d_p_cam->noalias() = d_uv_d_xy * d_xy_d_p;
    return true;
  }

  /// Derivative of a pixel with respect to the 18 intrinsics (row-major, as
  /// Ceres stores a parameter block's Jacobian).
  using IntrinsicsJacobian = Eigen::Matrix<double, 2, kNumParams, Eigen::RowMajor>;

  /// Project() with the derivatives of the pixel with respect to the point
  /// (2×3) and to the intrinsics `params` (for solves that refine them).
  /// `Jet` is ceres::Jet<double, 2 + kNumDistortion>: the distortion goes
  /// through jets over the two normalised coordinates and the 14
  /// coefficients; focal length and principal point enter linearly.
  template <typename Jet>
  static bool ProjectWithIntrinsicsJacobian(const double* params, const double* p_cam, double* uv,
                                            Eigen::Matrix<double, 2, 3>* d_uv_d_p_cam,
                                            IntrinsicsJacobian* d_uv_d_params) {
    if (!(p_cam[2] > 0)) return false;
    const double inv_z = 1.0 / p_cam[2];
    const double x = p_cam[0] / p_cam[2], y = p_cam[1] / p_cam[2];
    Jet jets[kNumParams];
    for (int k = 0; k < 4; ++k) jets[k] = Jet(params[k]);
    for (int k = 0; k < kNumDistortion; ++k) jets[4 + k] = Jet(params[4 + k], 2 + k);
    Jet xd, yd;
    Distort(jets, Jet(x, 0), Jet(y, 1), &xd, &yd);
    const double fx = params[0], fy = params[1];
    Eigen::Matrix<double, 2, 2> d_uv_d_xy;
    d_uv_d_xy << fx * xd.v[0], fx * xd.v[1], fy * yd.v[0], fy * yd.v[1];
    Eigen::Matrix<double, 2, 3> d_xy_d_p;
    d_xy_d_p << inv_z, 0.0, -x * inv_z, 0.0, inv_z, -y * inv_z;
    *d_uv_d_params = IntrinsicsJacobian::Zero();
    (*d_uv_d_params)(0, 0) = xd.a;
    (*d_uv_d_params)(1, 1) = yd.a;
    (*d_uv_d_params)(0, 2) = 1.0;
    (*d_uv_d_params)(1, 3) = 1.0;
    for (int k = 0; k < kNumDistortion; ++k) {
      (*d_uv_d_params)(0, 4 + k) = fx * xd.v[2 + k];
      (*d_uv_d_params)(1, 4 + k) = fy * yd.v[2 + k];
    }
    uv[0] = fx * xd.a + params[2];
    uv[1] = fy * yd.a + params[3];
    d_uv_d_p_cam->noalias() = d_uv_d_xy * d_xy_d_p;
    return true;
  }
};

/// One camera: name, image size and intrinsics in OpenCVCameraModel order.
/// A plain value; its frame is the OpenCV optical frame (x right, y down, z forward).
struct Camera {
  std::string name;  ///< unique in a dataset, without '/'
  int width = 0;   ///< pixels
  int height = 0;  ///< pixels
  /// fx, fy, cx, cy then 14 distortion coefficients (unused ones zero).
  std::array<double, OpenCVCameraModel::kNumParams> params{};
  /// How many distortion coefficients the input gave (0, 4, 5, 8, 12 or 14);
  /// kept so a file is written back the way it was read.
  int num_distortion = 0;
  /// False when the dataset gave no intrinsics (only the image size): params
  /// are then a placeholder until Calibrate() estimates them from the views.
  bool has_intrinsics = true;

  /// Builds a camera; `distortion` must have 0, 4, 5, 8, 12 or 14 entries.
  /// Returns nullopt and says why when it has not, or an entry is not finite,
  /// or fx, fy or the size is not positive.
  static std::optional<Camera> Make(std::string name, int width, int height, double fx, double fy,
                                    double cx, double cy, const std::vector<double>& distortion,
                                    std::string* why);

  double fx() const { return params[0]; }  ///< focal length along x, pixels
  double fy() const { return params[1]; }  ///< focal length along y, pixels
  double cx() const { return params[2]; }  ///< principal point, pixels (SPEC §2 origin)
  double cy() const { return params[3]; }  ///< principal point, pixels
  /// The distortion coefficients as given (num_distortion entries).
  std::vector<double> Distortion() const;
  /// The name of parameter `index` in OpenCVCameraModel order ("fx", "k1", "tau_x", …).
  static const char* ParamName(int index);
  /// True when a distortion coefficient is non-zero.
  bool HasDistortion() const;

  /// Pixel of a point in the camera frame; nullopt behind the camera.
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& p_cam) const;

  /// Inverse of the distortion: the normalised point (x, y) with
  /// Distort(x, y) = the pixel's distorted normalised point, so the ray through
  /// the pixel is (x, y, 1). Newton iterations from the undistorted guess;
  /// nullopt when they do not converge to 1e-12 (pixel far outside the
  /// model's valid domain).
  std::optional<Eigen::Vector2d> Undistort(const Eigen::Vector2d& uv) const;

  /// True when the pixel lies inside the image (with `margin` pixels kept clear).
  bool InImage(const Eigen::Vector2d& uv, double margin = 0.0) const {
    return uv.x() >= -0.5 + margin && uv.y() >= -0.5 + margin && uv.x() <= width - 0.5 - margin &&
           uv.y() <= height - 0.5 - margin;
  }
};

}  // namespace handeye
