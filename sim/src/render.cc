// SPDX-License-Identifier: GPL-2.0-or-later
// Off-screen renderer: every pixel that may see the target is ray cast through
// the camera's own distortion model (Camera::Undistort), so the image agrees
// with Camera::Project to far below the accuracy a detector can reach. Warping
// a pinhole image instead would resample it and bias the edges.
#include "handeye/sim/render.h"

#include <ceres/jet.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace handeye {

bool RenderOptions::Check(std::string* why) const {
  auto fail = [why](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  if (supersampling < 1 || supersampling > 64) return fail("supersampling in [1, 64]");
  if (!std::isfinite(blur_sigma_px) || blur_sigma_px < 0) return fail("blur_sigma_px >= 0");
  if (!std::isfinite(noise_sigma) || noise_sigma < 0) return fail("noise_sigma >= 0");
  for (const auto& [name, quality] : camera_quality)
    if (!std::isfinite(quality.blur_sigma_px) || quality.blur_sigma_px < 0 ||
        !std::isfinite(quality.noise_sigma) || quality.noise_sigma < 0)
      return fail("camera " + name + "'s blur and noise >= 0");
  if (!std::isfinite(black_level) || !std::isfinite(white_level) || black_level < 0 ||
      white_level > 255 || !(black_level < white_level))
    return fail("0 <= black_level < white_level <= 255");
  if (!std::isfinite(background_level) || background_level < 0 || background_level > 255)
    return fail("0 <= background_level <= 255");
  return true;
}

namespace {

/// Sample value of a ray that misses the printed sheet: the background shows.
constexpr float kMiss = -1.0f;

/// SplitMix64: turns one user seed into independent seeds for the background
/// and the noise, so changing one stream's use does not shift the other.
std::uint64_t MixSeed(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// Rays through pixels: the normalised point (x, y) with Distort(x, y) equal to
/// the pixel's distorted normalised point. Newton warm-started from the
/// neighbouring pixel's ray needs fewer steps than Camera::Undistort, which
/// starts from the undistorted point for every pixel; it stops at the same
/// 1e-14 residual, and Camera::Undistort stays the fallback.
class RayTracer {
 public:
  explicit RayTracer(const Camera& camera) : camera_(camera), distorted_(camera.HasDistortion()) {
    for (int i = 0; i < OpenCVCameraModel::kNumParams; ++i) jet_params_[i] = Jet(camera.params[i]);
  }

  /// Ray through pixel `uv`, starting Newton from `guess` when given. Returns
  /// false where the model cannot be inverted (far outside its valid domain).
  bool Ray(double u, double v, const Eigen::Vector2d* guess, Eigen::Vector2d* ray) const {
    const Eigen::Vector2d target((u - camera_.cx()) / camera_.fx(),
                                 (v - camera_.cy()) / camera_.fy());
    if (!distorted_) {
      *ray = target;
      return true;
    }
    if (guess && guess->allFinite()) {
      Eigen::Vector2d x = *guess;
      for (int iter = 0; iter < 8; ++iter) {
        Jet xd, yd;
        OpenCVCameraModel::Distort(jet_params_.data(), Jet(x.x(), 0), Jet(x.y(), 1), &xd, &yd);
        const Eigen::Vector2d r(xd.a - target.x(), yd.a - target.y());
        if (!r.allFinite()) break;
        if (r.norm() < 1e-14) {
          *ray = x;
          return true;
        }
        Eigen::Matrix2d J;
        J << xd.v[0], xd.v[1], yd.v[0], yd.v[1];
        const double det = J.determinant();
        // A vanishing Jacobian means a fold of the model: let the reference decide.
        if (!(std::abs(det) > 1e-9)) break;
        x -= J.inverse() * r;
      }
    }
    const auto reference = camera_.Undistort(Eigen::Vector2d(u, v));
    if (!reference) return false;
    *ray = *reference;
    return true;
  }

 private:
  using Jet = ceres::Jet<double, 2>;
  const Camera& camera_;
  bool distorted_;
  std::array<Jet, OpenCVCameraModel::kNumParams> jet_params_;
};

/// What a ray sees on the target plane: the sheet's albedo or kMiss.
class PlaneSampler {
 public:
  PlaneSampler(const Target& target, const Eigen::Isometry3d& T_cam_target, bool see_through)
      : target_(target), extent_(target.Extent()) {
    // A point (X, Y, 0) of the target plane is seen along the ray
    // λ (x, y, 1) = [r1 r2 t] (X, Y, 1) with depth λ > 0.
    Eigen::Matrix3d H;
    H.col(0) = T_cam_target.linear().col(0);
    H.col(1) = T_cam_target.linear().col(1);
    H.col(2) = T_cam_target.translation();
    // The printed face is seen from the target's -z side (camera centre at
    // z < 0 in the target frame); from the other side a printed sheet is a
    // plain back, a glass one shows the pattern mirrored (the same albedo
    // seen through the plane).
    const double camera_z_target = (T_cam_target.inverse()).translation().z();
    visible_ = std::abs(H.determinant()) > 1e-15 && camera_z_target != 0;
    plain_back_ = camera_z_target > 0 && !see_through;
    if (visible_) H_inv_ = H.inverse();
  }

  bool visible() const { return visible_; }

  float Sample(const Eigen::Vector2d& ray) const {
    if (!ray.allFinite()) return kMiss;
    const Eigen::Vector3d w = H_inv_ * Eigen::Vector3d(ray.x(), ray.y(), 1.0);
    if (!(w.z() > 0)) return kMiss;  // the plane lies behind the camera along this ray
    const double X = w.x() / w.z(), Y = w.y() / w.z();
    if (!(X >= extent_.min().x() && X <= extent_.max().x() && Y >= extent_.min().y() &&
          Y <= extent_.max().y()))
      return kMiss;
    return plain_back_ ? kBackAlbedo : static_cast<float>(target_.Albedo(X, Y));
  }

 private:
  const Target& target_;
  Eigen::AlignedBox2d extent_;
  Eigen::Matrix3d H_inv_ = Eigen::Matrix3d::Zero();
  bool visible_ = false;
  bool plain_back_ = false;
  /// The unprinted back of a sheet: light grey board.
  static constexpr float kBackAlbedo = 0.8f;
};

/// Pixel rectangle [u0, u1] × [v0, v1] (inclusive) that holds every pixel that
/// can see the sheet, or false when the sheet is not in view at all.
bool SheetBoundingBox(const Camera& camera, const Target& target,
                      const Eigen::Isometry3d& T_cam_target, cv::Rect* box) {
  const Eigen::AlignedBox2d extent = target.Extent();
  const Eigen::Vector2d lo = extent.min(), hi = extent.max();
  const Eigen::Vector2d corners[4] = {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}};
  // Dense outline: distortion bends the sheet's edges, so a bounding box of
  // the four corners alone could cut off a bulging edge.
  constexpr int kSamplesPerEdge = 256;
  double umin = std::numeric_limits<double>::infinity(), vmin = umin;
  double umax = -umin, vmax = -umin;
  bool whole_image = false;
  for (int e = 0; e < 4 && !whole_image; ++e) {
    for (int k = 0; k < kSamplesPerEdge; ++k) {
      const double s = static_cast<double>(k) / kSamplesPerEdge;
      const Eigen::Vector2d p = (1 - s) * corners[e] + s * corners[(e + 1) % 4];
      const Eigen::Vector3d p_cam = T_cam_target * Eigen::Vector3d(p.x(), p.y(), 0.0);
      const auto uv = camera.Project(p_cam);
      // Part of the sheet behind the camera, or projected through a fold of the
      // distortion polynomial (far outside its valid domain) where the outline
      // no longer bounds the image of the sheet: cast rays everywhere.
      if (!uv || !uv->allFinite()) {
        whole_image = true;
        break;
      }
      if (camera.HasDistortion()) {
        const auto back = camera.Undistort(*uv);
        const Eigen::Vector2d xy(p_cam.x() / p_cam.z(), p_cam.y() / p_cam.z());
        if (!back || (*back - xy).norm() > 1e-6 * (1.0 + xy.norm())) {
          whole_image = true;
          break;
        }
      }
      umin = std::min(umin, uv->x());
      umax = std::max(umax, uv->x());
      vmin = std::min(vmin, uv->y());
      vmax = std::max(vmax, uv->y());
    }
  }
  if (whole_image) {
    *box = cv::Rect(0, 0, camera.width, camera.height);
    return true;
  }
  // Generous padding: the outline is sampled, not continuous.
  const double pad = 3.0 + 0.01 * std::max(umax - umin, vmax - vmin);
  const double u0 = std::max(0.0, std::floor(umin - pad));
  const double v0 = std::max(0.0, std::floor(vmin - pad));
  const double u1 = std::min(camera.width - 1.0, std::ceil(umax + pad));
  const double v1 = std::min(camera.height - 1.0, std::ceil(vmax + pad));
  if (u1 < u0 || v1 < v0) return false;
  *box = cv::Rect(static_cast<int>(u0), static_cast<int>(v0), static_cast<int>(u1 - u0) + 1,
                  static_cast<int>(v1 - v0) + 1);
  return true;
}

/// Deterministic clutter: a shaded backdrop with shapes and lines of several
/// grey levels and sizes, under a smooth illumination field, so detectors are
/// tested against edges and corners that are not the target's.
cv::Mat MakeBackground(int width, int height, const RenderOptions& options) {
  if (!options.clutter) return cv::Mat(height, width, CV_32F, cv::Scalar(options.background_level));
  cv::RNG rng(MixSeed(options.seed) | 1);
  cv::Mat canvas(height, width, CV_8U);
  // Backdrop: a linear ramp between two grey levels in a random direction.
  {
    const double g0 = rng.uniform(40.0, 200.0), g1 = rng.uniform(40.0, 200.0);
    const double angle = rng.uniform(0.0, 2 * CV_PI);
    const double cu = std::cos(angle) / std::max(width, height);
    const double sv = std::sin(angle) / std::max(width, height);
    for (int v = 0; v < height; ++v) {
      auto* row = canvas.ptr<std::uint8_t>(v);
      for (int u = 0; u < width; ++u) {
        const double s =
            std::clamp(0.5 + (u - width / 2.0) * cu + (v - height / 2.0) * sv, 0.0, 1.0);
        row[u] = cv::saturate_cast<std::uint8_t>(g0 + s * (g1 - g0));
      }
    }
  }
  const double diagonal = std::hypot(width, height);
  auto random_point = [&] {
    return cv::Point(rng.uniform(-width / 10, width + width / 10),
                     rng.uniform(-height / 10, height + height / 10));
  };
  // Sizes log-uniform from a few pixels to half the image.
  auto random_size = [&] { return std::exp(rng.uniform(std::log(6.0), std::log(0.5 * diagonal))); };
  auto random_grey = [&] { return cv::Scalar(rng.uniform(0, 256)); };
  const int num_shapes = 40 + static_cast<int>(diagonal / 40);
  for (int k = 0; k < num_shapes; ++k) {
    const int kind = rng.uniform(0, 4);
    const cv::Point centre = random_point();
    const double size = random_size();
    if (kind == 0) {  // filled rotated rectangle
      const cv::RotatedRect rect(centre, cv::Size2f(size, size * rng.uniform(0.2, 1.0)),
                                 rng.uniform(0.0f, 180.0f));
      cv::Point2f pts[4];
      rect.points(pts);
      std::vector<cv::Point> poly(pts, pts + 4);
      cv::fillConvexPoly(canvas, poly, random_grey(), cv::LINE_AA);
    } else if (kind == 1) {  // ellipse, filled or outlined
      const int thickness = rng.uniform(0, 3) == 0 ? rng.uniform(1, 6) : cv::FILLED;
      cv::ellipse(canvas, centre, cv::Size(size / 2, size * rng.uniform(0.1, 0.5)),
                  rng.uniform(0.0, 180.0), 0, 360, random_grey(), thickness, cv::LINE_AA);
    } else if (kind == 2) {  // straight line
      const double a = rng.uniform(0.0, CV_PI);
      const cv::Point d(static_cast<int>(size * std::cos(a)), static_cast<int>(size * std::sin(a)));
      cv::line(canvas, centre - d, centre + d, random_grey(), rng.uniform(1, 9), cv::LINE_AA);
    } else {  // shaded patch: a small ramp inside a rectangle
      const int w = std::max(2, static_cast<int>(size)),
                h = std::max(2, static_cast<int>(size * rng.uniform(0.3, 1.0)));
      const cv::Rect patch =
          cv::Rect(centre.x - w / 2, centre.y - h / 2, w, h) & cv::Rect(0, 0, width, height);
      if (patch.area() == 0) continue;
      const double g0 = rng.uniform(0.0, 255.0), g1 = rng.uniform(0.0, 255.0);
      for (int v = patch.y; v < patch.y + patch.height; ++v) {
        auto* row = canvas.ptr<std::uint8_t>(v);
        for (int u = patch.x; u < patch.x + patch.width; ++u)
          row[u] = cv::saturate_cast<std::uint8_t>(g0 + (g1 - g0) * (u - patch.x) / patch.width);
      }
    }
  }
  cv::Mat background;
  canvas.convertTo(background, CV_32F);
  // Low-frequency illumination: a coarse random gain field, smoothly upsampled.
  cv::Mat gain(4, 6, CV_32F);
  for (int v = 0; v < gain.rows; ++v)
    for (int u = 0; u < gain.cols; ++u)
      gain.at<float>(v, u) = static_cast<float>(rng.uniform(0.75, 1.2));
  cv::resize(gain, gain, cv::Size(width, height), 0, 0, cv::INTER_CUBIC);
  cv::multiply(background, gain, background);
  return background;
}

/// Renders the sheet into `image` (float grey levels over the background),
/// touching only pixels inside `box`.
void CastSheet(const Camera& camera, const PlaneSampler& sampler, const cv::Rect& box,
               const RenderOptions& options, cv::Mat* image) {
  const int nu = box.width, nv = box.height;
  const int stride = nu + 1;
  // Rays and sample values at pixel corners (u ± 0.5, v ± 0.5), shared by the
  // four pixels around each corner.
  std::vector<Eigen::Vector2d> corner_ray(static_cast<size_t>(stride) * (nv + 1));
  std::vector<float> corner_value(corner_ray.size());
  const RayTracer tracer(camera);
  cv::parallel_for_(cv::Range(0, nv + 1), [&](const cv::Range& rows) {
    for (int cv_ = rows.start; cv_ < rows.end; ++cv_) {
      const double v = box.y - 0.5 + cv_;
      Eigen::Vector2d previous =
          Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
      for (int cu = 0; cu <= nu; ++cu) {
        const double u = box.x - 0.5 + cu;
        Eigen::Vector2d ray;
        if (!tracer.Ray(u, v, &previous, &ray))
          ray.setConstant(std::numeric_limits<double>::quiet_NaN());
        previous = ray;
        corner_ray[static_cast<size_t>(cv_) * stride + cu] = ray;
        corner_value[static_cast<size_t>(cv_) * stride + cu] = sampler.Sample(ray);
      }
    }
  });

  // A pixel whose corners and centre all see the same value is taken as
  // uniform. The mask of the others is dilated by one pixel: a sharp tip of a
  // shape can poke into a pixel between its corners, but it then also crosses
  // a corner of a neighbouring pixel.
  cv::Mat mixed(nv, nu, CV_8U, cv::Scalar(0));
  cv::Mat uniform_value(nv, nu, CV_32F);
  auto bilinear = [&](int pu, int pv, double fu, double fv) {
    // fu, fv in [0, 1] across the pixel from its top-left corner.
    const size_t i00 = static_cast<size_t>(pv) * stride + pu;
    return Eigen::Vector2d(
        (1 - fv) * ((1 - fu) * corner_ray[i00] + fu * corner_ray[i00 + 1]) +
        fv * ((1 - fu) * corner_ray[i00 + stride] + fu * corner_ray[i00 + stride + 1]));
  };
  cv::parallel_for_(cv::Range(0, nv), [&](const cv::Range& rows) {
    for (int pv = rows.start; pv < rows.end; ++pv) {
      auto* mixed_row = mixed.ptr<std::uint8_t>(pv);
      auto* value_row = uniform_value.ptr<float>(pv);
      for (int pu = 0; pu < nu; ++pu) {
        const size_t i00 = static_cast<size_t>(pv) * stride + pu;
        const float c = sampler.Sample(bilinear(pu, pv, 0.5, 0.5));
        value_row[pu] = c;
        mixed_row[pu] = (corner_value[i00] != c || corner_value[i00 + 1] != c ||
                         corner_value[i00 + stride] != c || corner_value[i00 + stride + 1] != c)
                            ? 1
                            : 0;
      }
    }
  });
  cv::dilate(mixed, mixed, cv::Mat::ones(3, 3, CV_8U));

  // Sample positions (fractions of the pixel from its top-left corner): one
  // per cell of an n × n split, and within its cell shifted so that all n²
  // samples have distinct u and distinct v ("n-rooks"). A plain grid has only
  // n distinct columns, so an edge along the pixel grid would be placed to
  // 1/(2n) px; here to 1/(2n²). The pattern is point-symmetric about the
  // pixel centre, which keeps the rendering unbiased.
  const int n = options.supersampling;
  std::vector<std::pair<double, double>> pattern;
  pattern.reserve(static_cast<size_t>(n) * n);
  for (int k = 0; k < n; ++k)
    for (int l = 0; l < n; ++l)
      pattern.emplace_back((k * n + l + 0.5) / (n * n), (l * n + k + 0.5) / (n * n));
  const double contrast = options.white_level - options.black_level;
  cv::Mat roi = (*image)(box);
  cv::parallel_for_(cv::Range(0, nv), [&](const cv::Range& rows) {
    for (int pv = rows.start; pv < rows.end; ++pv) {
      const auto* mixed_row = mixed.ptr<std::uint8_t>(pv);
      const auto* value_row = uniform_value.ptr<float>(pv);
      auto* out = roi.ptr<float>(pv);
      for (int pu = 0; pu < nu; ++pu) {
        if (!mixed_row[pu]) {
          if (value_row[pu] != kMiss)
            out[pu] = static_cast<float>(options.black_level + contrast * value_row[pu]);
          continue;
        }
        // Box filter over the pixel's area with n × n samples.
        double albedo_sum = 0;
        int hits = 0;
        for (const auto& [fu, fv] : pattern) {
          const float a = sampler.Sample(bilinear(pu, pv, fu, fv));
          if (a == kMiss) continue;
          albedo_sum += a;
          ++hits;
        }
        const double coverage = static_cast<double>(hits) / (n * n);
        const double sheet = hits ? options.black_level + contrast * albedo_sum / hits : 0.0;
        out[pu] = static_cast<float>(coverage * sheet + (1 - coverage) * out[pu]);
      }
    }
  });
}

}  // namespace

cv::Mat RenderView(const Camera& camera, const Target& target,
                   const Eigen::Isometry3d& T_cam_target, const RenderOptions& options) {
  std::string why;
  if (!options.Check(&why)) throw std::invalid_argument("RenderView: expected " + why);
  if (camera.width <= 0 || camera.height <= 0)
    throw std::invalid_argument("RenderView: camera has no image size");

  cv::Mat image = MakeBackground(camera.width, camera.height, options);
  const PlaneSampler sampler(target, T_cam_target, options.see_through);
  cv::Rect box;
  if (sampler.visible() && SheetBoundingBox(camera, target, T_cam_target, &box))
    CastSheet(camera, sampler, box, options, &image);

  if (options.blur_sigma_px > 0) {
    // At least 4σ each side, so the kernel's truncation does not skew edges.
    const int half = std::max(1, static_cast<int>(std::ceil(4.0 * options.blur_sigma_px)));
    cv::GaussianBlur(image, image, cv::Size(2 * half + 1, 2 * half + 1), options.blur_sigma_px,
                     options.blur_sigma_px, cv::BORDER_REFLECT);
  }
  if (options.noise_sigma > 0) {
    cv::Mat noise(image.size(), CV_32F);
    cv::RNG rng(MixSeed(options.seed ^ 0x6e6f697365ULL) | 1);  // "noise"
    rng.fill(noise, cv::RNG::NORMAL, 0.0, options.noise_sigma);
    image += noise;
  }
  cv::Mat gray;
  image.convertTo(gray, CV_8U);  // rounds to nearest and saturates
  return gray;
}

}  // namespace handeye
