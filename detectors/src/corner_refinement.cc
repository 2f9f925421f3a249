// SPDX-License-Identifier: GPL-2.0-or-later
#include "corner_refinement.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>

namespace handeye::internal {

Gradients SobelGradients(const cv::Mat& gray, const cv::Rect& region) {
  Gradients g;
  const cv::Rect inside = region & cv::Rect(0, 0, gray.cols, gray.rows);
  g.origin = inside.tl();
  if (inside.empty()) return g;
  // On a region of a larger image OpenCV's filters read the pixels around it;
  // only the image's own border is repeated.
  cv::Sobel(gray(inside), g.gx, CV_32F, 1, 0, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
  cv::Sobel(gray(inside), g.gy, CV_32F, 0, 1, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
  return g;
}

std::optional<Eigen::Vector2d> RefineXCorner(const Gradients& g, const Eigen::Vector2d& guess,
                                             const Eigen::Matrix2d& window, double max_shift_px) {
  if (!guess.allFinite() || !window.allFinite() || g.gx.empty()) return std::nullopt;
  const Eigen::JacobiSVD<Eigen::Matrix2d> svd(window);
  const double widest_px = svd.singularValues()(0), narrowest_px = svd.singularValues()(1);
  // Below a pixel across, the window holds no gradient pattern; beyond
  // 100 px the caller's scale estimate broke down.
  if (!(narrowest_px >= 1.0 && widest_px <= 100) || !(max_shift_px >= 0 && max_shift_px <= 100))
    return std::nullopt;
  const Eigen::Matrix2d to_unit = window.inverse();
  // Gaussian weight of σ = half the window, in the window's unit coordinates.
  constexpr double kInvTwoSigma2 = 1.0 / (2.0 * 0.5 * 0.5);
  const int x_end = g.origin.x + g.gx.cols - 1, y_end = g.origin.y + g.gx.rows - 1;
  Eigen::Vector2d c = guess;
  for (int iter = 0; iter < 40; ++iter) {
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Eigen::Vector2d b = Eigen::Vector2d::Zero();
    const int x0 = std::max(g.origin.x, static_cast<int>(std::floor(c.x() - widest_px)));
    const int x1 = std::min(x_end, static_cast<int>(std::ceil(c.x() + widest_px)));
    const int y0 = std::max(g.origin.y, static_cast<int>(std::floor(c.y() - widest_px)));
    const int y1 = std::min(y_end, static_cast<int>(std::ceil(c.y() + widest_px)));
    for (int y = y0; y <= y1; ++y) {
      const float* row_x = g.gx.ptr<float>(y - g.origin.y) - g.origin.x;
      const float* row_y = g.gy.ptr<float>(y - g.origin.y) - g.origin.x;
      for (int x = x0; x <= x1; ++x) {
        const double r2 = (to_unit * (Eigen::Vector2d(x, y) - c)).squaredNorm();
        if (r2 > 1.0) continue;
        const double g0 = row_x[x], g1 = row_y[x];
        const double w = std::exp(-r2 * kInvTwoSigma2);
        const double a00 = w * g0 * g0, a01 = w * g0 * g1, a11 = w * g1 * g1;
        A(0, 0) += a00;
        A(0, 1) += a01;
        A(1, 1) += a11;
        b.x() += a00 * x + a01 * y;
        b.y() += a01 * x + a11 * y;
      }
    }
    A(1, 0) = A(0, 1);
    // Both edge directions must be present: a single straight edge (or flat
    // paper) leaves the point free to slide along it. Two ideal edges at
    // angle θ give eigenvalues in the ratio tan²(θ/2): 0.02 is θ = 16°.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(A, Eigen::EigenvaluesOnly);
    const double lmin = eig.eigenvalues()(0), lmax = eig.eigenvalues()(1);
    if (!(lmax > 0) || lmin < 0.02 * lmax) return std::nullopt;
    const Eigen::Vector2d next = A.ldlt().solve(b);
    if (!next.allFinite()) return std::nullopt;
    const double step = (next - c).norm();
    c = next;
    if ((c - guess).norm() > max_shift_px) return std::nullopt;
    if (step < 1e-4) break;
  }
  return c;
}

std::optional<Eigen::Vector2d> RefineXCorner(const cv::Mat& gray, const Eigen::Vector2d& guess,
                                             const Eigen::Matrix2d& window, double max_shift_px,
                                             const std::function<bool(int x, int y)>& keep) {
  if (!guess.allFinite() || !window.allFinite() || !std::isfinite(max_shift_px))
    return std::nullopt;
  // Pixels the window can reach while the estimate stays within
  // max_shift_px, plus one for the gradient stencil; clamped in floating
  // point, so a guess far outside the image cannot overflow the bounds. The
  // image's outermost pixels are left out (their gradient is one-sided).
  const double widest_px = Eigen::JacobiSVD<Eigen::Matrix2d>(window).singularValues()(0);
  const double reach = std::min(widest_px, 100.0) + std::clamp(max_shift_px, 0.0, 100.0) + 1.0;
  auto clamp_to = [](double v, int lo, int hi) {
    return static_cast<int>(std::clamp(v, static_cast<double>(lo), static_cast<double>(hi)));
  };
  const int x0 = clamp_to(std::floor(guess.x() - reach), 1, gray.cols - 2);
  const int y0 = clamp_to(std::floor(guess.y() - reach), 1, gray.rows - 2);
  const int x1 = clamp_to(std::ceil(guess.x() + reach), 1, gray.cols - 2);
  const int y1 = clamp_to(std::ceil(guess.y() + reach), 1, gray.rows - 2);
  if (x1 - x0 < 2 || y1 - y0 < 2) return std::nullopt;
  Gradients g = SobelGradients(gray, cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1));
  if (keep) {
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        if (!keep(x, y)) g.gx.at<float>(y - y0, x - x0) = g.gy.at<float>(y - y0, x - x0) = 0.0f;
  }
  return RefineXCorner(g, guess, window, max_shift_px);
}

std::optional<EdgeLine> FitEdge(const cv::Mat& gray, const Eigen::Vector2d& from,
                                const Eigen::Vector2d& to, double extend_px, double skip_px,
                                double half_width_px) {
  const double length = (to - from).norm();
  if (!(length > 0 && length < 1e5) || !from.allFinite() || !to.allFinite() ||
      !(half_width_px > 0 && half_width_px < 100) || !(extend_px >= 0 && extend_px < 1e5))
    return std::nullopt;
  Eigen::Vector2d along = (to - from) / length;
  EdgeLine line{Eigen::Vector2d(-along.y(), along.x()), 0.0};
  line.offset = line.normal.dot(from);
  for (int iter = 0; iter < 30; ++iter) {
    // The band's corners bound the pixels to visit.
    const Eigen::Vector2d base = from - line.normal * (line.normal.dot(from) - line.offset);
    const Eigen::Vector2d ends[2] = {base - extend_px * along, base + (length + extend_px) * along};
    double umin = 1e300, umax = -1e300, vmin = 1e300, vmax = -1e300;
    for (const Eigen::Vector2d& end : ends) {
      for (double side : {-1.0, 1.0}) {
        const Eigen::Vector2d p = end + side * (half_width_px + 1.0) * line.normal;
        umin = std::min(umin, p.x());
        umax = std::max(umax, p.x());
        vmin = std::min(vmin, p.y());
        vmax = std::max(vmax, p.y());
      }
    }
    // Clipped to the image (less the gradient stencil's rim): an edge that
    // runs out of the image is fitted on the part inside.
    auto clamp_to = [](double v, int lo, int hi) {
      return static_cast<int>(std::clamp(v, static_cast<double>(lo), static_cast<double>(hi)));
    };
    const int x0 = clamp_to(std::floor(umin), 1, gray.cols - 2);
    const int x1 = clamp_to(std::ceil(umax), 1, gray.cols - 2);
    const int y0 = clamp_to(std::floor(vmin), 1, gray.rows - 2);
    const int y1 = clamp_to(std::ceil(vmax), 1, gray.rows - 2);
    if (x1 <= x0 || y1 <= y0) return std::nullopt;
    double weight_sum = 0;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
    for (int y = y0; y <= y1; ++y) {
      const auto* up = gray.ptr<std::uint8_t>(y - 1);
      const auto* mid = gray.ptr<std::uint8_t>(y);
      const auto* down = gray.ptr<std::uint8_t>(y + 1);
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d p(x, y);
        const double t = along.dot(p - base);
        const double d = line.normal.dot(p) - line.offset;
        if (t < -extend_px || t > length + extend_px || std::abs(d) > half_width_px) continue;
        if (std::abs(t) < skip_px || std::abs(t - length) < skip_px) continue;
        const double gx =
            (up[x + 1] - up[x - 1]) + 2.0 * (mid[x + 1] - mid[x - 1]) + (down[x + 1] - down[x - 1]);
        const double gy =
            (down[x - 1] - up[x - 1]) + 2.0 * (down[x] - up[x]) + (down[x + 1] - up[x + 1]);
        const double g = gx * line.normal.x() + gy * line.normal.y();
        const double w = g * g;
        weight_sum += w;
        mean += w * p;
        second += w * p * p.transpose();
      }
    }
    // Less than a short edge's worth of gradient: nothing to fit.
    if (!(weight_sum > 1e4)) return std::nullopt;
    mean /= weight_sum;
    const Eigen::Matrix2d scatter = second / weight_sum - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
    Eigen::Vector2d next_along = eig.eigenvectors().col(1);
    if (next_along.dot(along) < 0) next_along = -next_along;
    const EdgeLine next{Eigen::Vector2d(-next_along.y(), next_along.x()),
                        Eigen::Vector2d(-next_along.y(), next_along.x()).dot(mean)};
    // How far the fitted line moved, at the edge's two ends.
    const double moved = std::abs(next.normal.dot(base) - next.offset) +
                         std::abs(next.normal.dot(base + length * along) - next.offset);
    along = next_along;
    line = next;
    if (moved < 1e-3) break;
  }
  return line;
}

std::optional<Eigen::Vector2d> Intersect(const EdgeLine& a, const EdgeLine& b) {
  Eigen::Matrix2d A;
  A.row(0) = a.normal.transpose();
  A.row(1) = b.normal.transpose();
  const double det = A.determinant();
  // Edges closer than about 6° to parallel give an ill-defined corner.
  if (std::abs(det) < 0.1) return std::nullopt;
  return A.inverse() * Eigen::Vector2d(a.offset, b.offset);
}

bool SpansPlane(const std::vector<Eigen::Vector2d>& points, double min_spread_m) {
  if (points.size() < 3) return false;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : points) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  const Eigen::Vector2d normal = eig.eigenvectors().col(0);  // across the best-fit line
  double spread = 0;
  for (const auto& p : points) spread = std::max(spread, std::abs(normal.dot(p - mean)));
  return spread >= min_spread_m;
}

namespace {

/// Similarity moving the points' centroid to 0 and their mean distance to √2
/// (Hartley normalisation), so the DLT is well conditioned.
Eigen::Matrix3d Normaliser(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  double spread = 0;
  for (const auto& p : points) spread += (p - mean).norm();
  spread /= static_cast<double>(points.size());
  const double s = spread > 0 ? std::sqrt(2.0) / spread : 1.0;
  Eigen::Matrix3d T;
  T << s, 0, -s * mean.x(), 0, s, -s * mean.y(), 0, 0, 1;
  return T;
}

/// The DLT of a homography from `from` to `to`, both normalised (Normaliser):
/// two rows per point pair, each handed to `row`.
template <typename Row>
void ForEachDltRow(const std::vector<Eigen::Vector2d>& from, const std::vector<Eigen::Vector2d>& to,
                   const Eigen::Matrix3d& Tf, const Eigen::Matrix3d& Tt, const Row& row) {
  Eigen::Matrix<double, 9, 1> rx, ry;
  for (std::size_t i = 0; i < from.size(); ++i) {
    const Eigen::Vector3d p = Tf * from[i].homogeneous();
    const Eigen::Vector3d q = Tt * to[i].homogeneous();
    rx << p.x(), p.y(), 1, 0, 0, 0, -q.x() * p.x(), -q.x() * p.y(), -q.x();
    ry << 0, 0, 0, p.x(), p.y(), 1, -q.y() * p.x(), -q.y() * p.y(), -q.y();
    row(2 * i, rx);
    row(2 * i + 1, ry);
  }
}

/// The homography of the normalised solution `h` (row-major), taken back
/// through the normalisers; nullopt when it is not finite or maps to infinity.
std::optional<Eigen::Matrix3d> Denormalised(const Eigen::Matrix<double, 9, 1>& h,
                                            const Eigen::Matrix3d& Tf, const Eigen::Matrix3d& Tt) {
  Eigen::Matrix3d Hn;
  Hn << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  const Eigen::Matrix3d H = Tt.inverse() * Hn * Tf;
  if (!H.allFinite() || std::abs(H(2, 2)) < 1e-15) return std::nullopt;
  return H / H(2, 2);
}

}  // namespace

std::optional<Eigen::Matrix3d> FitHomography(const std::vector<Eigen::Vector2d>& from,
                                             const std::vector<Eigen::Vector2d>& to) {
  const std::size_t n = from.size();
  if (n < 4 || to.size() != n) return std::nullopt;
  const Eigen::Matrix3d Tf = Normaliser(from), Tt = Normaliser(to);
  Eigen::MatrixXd M(2 * n, 9);
  ForEachDltRow(from, to, Tf, Tt, [&M](std::size_t r, const Eigen::Matrix<double, 9, 1>& row) {
    M.row(static_cast<Eigen::Index>(r)) = row.transpose();
  });
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeFullV);
  const Eigen::VectorXd s = svd.singularValues();
  // A second vanishing singular value: the points do not fix H (e.g. three collinear).
  if (!(s(7) > 1e-9 * s(0))) return std::nullopt;
  return Denormalised(svd.matrixV().col(8), Tf, Tt);
}

std::optional<Eigen::Matrix3d> FitHomographyFast(const std::vector<Eigen::Vector2d>& from,
                                                 const std::vector<Eigen::Vector2d>& to) {
  const std::size_t n = from.size();
  if (n < 4 || to.size() != n) return std::nullopt;
  const Eigen::Matrix3d Tf = Normaliser(from), Tt = Normaliser(to);
  Eigen::Matrix<double, 9, 9> normal = Eigen::Matrix<double, 9, 9>::Zero();
  ForEachDltRow(from, to, Tf, Tt, [&normal](std::size_t, const Eigen::Matrix<double, 9, 1>& row) {
    normal += row * row.transpose();
  });
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eigen(normal);
  // A second vanishing eigenvalue: the points do not fix H.
  if (!(eigen.eigenvalues()(1) > 1e-12 * eigen.eigenvalues()(8))) return std::nullopt;
  return Denormalised(eigen.eigenvectors().col(0), Tf, Tt);
}

double Bilinear(const cv::Mat& gray, double x, double y) {
  x = std::clamp(x, 0.0, gray.cols - 1.001);
  y = std::clamp(y, 0.0, gray.rows - 1.001);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  const auto* r0 = gray.ptr<std::uint8_t>(y0);
  const auto* r1 = gray.ptr<std::uint8_t>(y0 + 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
         fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

std::optional<double> Pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const auto count = static_cast<double>(a.size());
  double ma = 0, mb = 0;
  for (std::size_t k = 0; k < a.size(); ++k) ma += a[k] / count, mb += b[k] / count;
  double aa = 0, bb = 0, ab = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    aa += (a[k] - ma) * (a[k] - ma);
    bb += (b[k] - mb) * (b[k] - mb);
    ab += (a[k] - ma) * (b[k] - mb);
  }
  if (!(aa > 0 && bb > 0)) return std::nullopt;
  return ab / std::sqrt(aa * bb);
}

}  // namespace handeye::internal
