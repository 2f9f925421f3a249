// SPDX-License-Identifier: GPL-2.0-or-later
#include "grid_patch.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace handeye::internal {
namespace {

/// Saddle points bucketed in square cells, for lookups by position.
class PointIndex {
 public:
  PointIndex(const std::vector<SaddlePoint>& saddles, int cell) : saddles_(saddles), cell_(cell) {
    int max_x = 0, max_y = 0;
    for (const SaddlePoint& s : saddles) {
      max_x = std::max(max_x, s.pixel.x);
      max_y = std::max(max_y, s.pixel.y);
    }
    cols_ = max_x / cell_ + 1;
    rows_ = max_y / cell_ + 1;
    cells_.resize(static_cast<std::size_t>(cols_) * rows_);
    for (int i = 0; i < static_cast<int>(saddles.size()); ++i)
      cells_[CellOf(saddles[i].pixel.x, saddles[i].pixel.y)].push_back(i);
  }

  /// Calls f(index, squared distance) for every point within `radius` of `c`.
  template <typename F>
  void ForEachWithin(const cv::Point2d& c, double radius, F f) const {
    const int x0 = std::max(0, static_cast<int>(std::floor((c.x - radius) / cell_)));
    const int x1 = std::min(cols_ - 1, static_cast<int>(std::floor((c.x + radius) / cell_)));
    const int y0 = std::max(0, static_cast<int>(std::floor((c.y - radius) / cell_)));
    const int y1 = std::min(rows_ - 1, static_cast<int>(std::floor((c.y + radius) / cell_)));
    const double r2 = radius * radius;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        for (const int i : cells_[static_cast<std::size_t>(y) * cols_ + x]) {
          const double dx = saddles_[i].pixel.x - c.x, dy = saddles_[i].pixel.y - c.y;
          const double d2 = dx * dx + dy * dy;
          if (d2 <= r2) f(i, d2);
        }
      }
    }
  }

 private:
  std::size_t CellOf(int x, int y) const {
    return static_cast<std::size_t>(y / cell_) * cols_ + x / cell_;
  }

  const std::vector<SaddlePoint>& saddles_;
  int cell_ = 1;
  int cols_ = 0, rows_ = 0;
  std::vector<std::vector<int>> cells_;
};

/// Cosine of the angle between two Hessians (Frobenius inner product): -1
/// between neighbouring corners of a checkerboard seen head-on (the same
/// X-junction with the colours swapped), +1 between diagonal ones; a plane
/// seen in perspective changes the junctions' angles little from one corner
/// to the next.
double HessianCosine(const SaddlePoint& a, const SaddlePoint& b) {
  const double ab = static_cast<double>(a.dxx) * b.dxx + 2.0 * a.dxy * b.dxy + static_cast<double>(a.dyy) * b.dyy;
  const double aa = static_cast<double>(a.dxx) * a.dxx + 2.0 * a.dxy * a.dxy + static_cast<double>(a.dyy) * a.dyy;
  const double bb = static_cast<double>(b.dxx) * b.dxx + 2.0 * b.dxy * b.dxy + static_cast<double>(b.dyy) * b.dyy;
  return ab / std::sqrt(aa * bb + 1e-30);
}

cv::Point2d At(const SaddlePoint& s) { return cv::Point2d(s.pixel.x, s.pixel.y); }

/// True when the Hessian's eigenvalues have opposite signs and the smaller
/// magnitude is at least `min_ratio` of the larger.
bool IsXJunction(const SaddlePoint& s, double min_ratio) {
  const double half_trace = 0.5 * (static_cast<double>(s.dxx) + s.dyy);
  const double det = static_cast<double>(s.dxx) * s.dyy - static_cast<double>(s.dxy) * s.dxy;
  if (!(det < 0)) return false;
  const double root = std::sqrt(half_trace * half_trace - det);
  const double larger = root + std::abs(half_trace), smaller = root - std::abs(half_trace);
  return smaller >= min_ratio * larger;
}

}  // namespace

bool HasGridPatch(const std::vector<SaddlePoint>& all_saddles, const GridPatchOptions& options) {
  std::vector<SaddlePoint> saddles;
  for (const SaddlePoint& s : all_saddles)
    if (IsXJunction(s, options.min_eigen_ratio)) saddles.push_back(s);
  if (saddles.size() < 6) return false;
  constexpr int kCellPx = 8;
  const PointIndex index(saddles, kCellPx);
  const double min_step2 = options.min_step_px * options.min_step_px;

  // A saddle point within `radius` of `c` whose Hessian has the sign `sign`
  // relative to `p`'s (+1 same, -1 opposite).
  auto any_near = [&](const cv::Point2d& c, double radius, const SaddlePoint& p, int sign) {
    bool found = false;
    index.ForEachWithin(c, radius, [&](int i, double) {
      found = found || sign * HessianCosine(p, saddles[i]) >= options.min_cosine;
    });
    return found;
  };

  std::vector<std::pair<double, int>> near;
  for (int i = 0; i < static_cast<int>(saddles.size()); ++i) {
    const SaddlePoint& p = saddles[i];
    // p's nearest points: a radius doubled until it holds enough of them.
    for (double radius = 4.0 * kCellPx;; radius *= 2) {
      const double r = std::min(radius, options.max_step_px);
      near.clear();
      index.ForEachWithin(At(p), r, [&](int j, double d2) {
        if (j != i && d2 >= min_step2) near.emplace_back(d2, j);
      });
      if (static_cast<int>(near.size()) >= options.neighbours || r >= options.max_step_px) break;
    }
    const std::size_t keep = std::min<std::size_t>(near.size(), options.neighbours);
    std::partial_sort(near.begin(), near.begin() + keep, near.end());
    near.resize(keep);

    for (const auto& neighbour : near) {
      // Named, not a structured binding: a lambda below uses q, and C++17
      // does not let lambdas capture bindings (clang refuses; g++ allows).
      const double du2 = neighbour.first;
      const int q = neighbour.second;
      // p + u: a neighbour along one grid line, so of opposite sign...
      if (!(-HessianCosine(p, saddles[q]) >= options.min_cosine)) continue;
      const cv::Point2d u = At(saddles[q]) - At(p);
      const double u_len = std::sqrt(du2);
      // ... and p - u on the other side.
      const cv::Point2d back_c = At(p) - u;
      const double tol_u = options.tolerance * u_len + options.slack_px;
      int back = -1;
      double back_d2 = tol_u * tol_u;
      index.ForEachWithin(back_c, tol_u, [&](int j, double d2) {
        if (d2 <= back_d2 && -HessianCosine(p, saddles[j]) >= options.min_cosine) back = j, back_d2 = d2;
      });
      if (back < 0) continue;
      for (const auto& [dv2, s] : near) {
        // p + v: a neighbour along the other grid line.
        if (s == q || s == back || !(-HessianCosine(p, saddles[s]) >= options.min_cosine)) continue;
        const cv::Point2d v = At(saddles[s]) - At(p);
        const double v_len = std::sqrt(dv2);
        if (std::abs(u.x * v.y - u.y * v.x) < options.min_sine * u_len * v_len) continue;
        // The diagonal neighbours p ± u + v have p's sign.
        const double tol = options.tolerance * std::min(u_len, v_len) + options.slack_px;
        if (!any_near(At(saddles[q]) + v, tol, p, +1) || !any_near(At(saddles[back]) + v, tol, p, +1))
          continue;
        if (options.rows == 2) return true;
        // Three rows: p - v, of the other sign, and p ± u - v, of p's.
        const double tol_v = options.tolerance * v_len + options.slack_px;
        int below = -1;
        double below_d2 = tol_v * tol_v;
        index.ForEachWithin(At(p) - v, tol_v, [&](int j, double d2) {
          if (d2 <= below_d2 && j != q && j != back && -HessianCosine(p, saddles[j]) >= options.min_cosine)
            below = j, below_d2 = d2;
        });
        if (below < 0) continue;
        const cv::Point2d w = At(saddles[below]) - At(p);
        if (any_near(At(saddles[q]) + w, tol, p, +1) && any_near(At(saddles[back]) + w, tol, p, +1))
          return true;
      }
    }
  }
  return false;
}

}  // namespace handeye::internal
