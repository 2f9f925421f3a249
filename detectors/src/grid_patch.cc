// SPDX-License-Identifier: GPL-2.0-or-later
#include "grid_patch.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <initializer_list>
#include <map>
#include <optional>
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
  const double ab =
      static_cast<double>(a.dxx) * b.dxx + 2.0 * a.dxy * b.dxy + static_cast<double>(a.dyy) * b.dyy;
  const double aa =
      static_cast<double>(a.dxx) * a.dxx + 2.0 * a.dxy * a.dxy + static_cast<double>(a.dyy) * a.dyy;
  const double bb =
      static_cast<double>(b.dxx) * b.dxx + 2.0 * b.dxy * b.dxy + static_cast<double>(b.dyy) * b.dyy;
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

/// The saddle points that are X-junctions (IsXJunction).
std::vector<SaddlePoint> XJunctions(const std::vector<SaddlePoint>& saddles,
                                    const GridPatchOptions& options) {
  std::vector<SaddlePoint> junctions;
  for (const SaddlePoint& s : saddles)
    if (IsXJunction(s, options.min_eigen_ratio)) junctions.push_back(s);
  return junctions;
}

/// Side of PointIndex's cells (px).
constexpr int kCellPx = 8;

}  // namespace

std::vector<GridPatch> FindGridPatches(const std::vector<SaddlePoint>& all_saddles,
                                       const GridPatchOptions& options, std::size_t max_patches) {
  std::vector<GridPatch> patches;
  const std::vector<SaddlePoint> saddles = XJunctions(all_saddles, options);
  if (saddles.size() < 6 || max_patches == 0) return patches;
  const PointIndex index(saddles, kCellPx);
  const double min_step2 = options.min_step_px * options.min_step_px;

  // The saddle point nearest to `c`, within `radius`, whose Hessian has the
  // sign `sign` relative to `p`'s (+1 same, -1 opposite) and that is not one
  // of `taken`; -1 if none.
  auto nearest = [&](const cv::Point2d& c, double radius, const SaddlePoint& p, int sign,
                     std::initializer_list<int> taken) {
    int best = -1;
    double best_d2 = radius * radius;
    index.ForEachWithin(c, radius, [&](int j, double d2) {
      if (d2 > best_d2 || std::find(taken.begin(), taken.end(), j) != taken.end()) return;
      if (sign * HessianCosine(p, saddles[j]) >= options.min_cosine) best = j, best_d2 = d2;
    });
    return best;
  };
  auto patch_of = [&](std::initializer_list<int> corners, double u_len, double v_len) {
    GridPatch patch;
    for (const int k : corners) patch.corners.push_back(saddles[k].pixel);
    patch.step_px = std::max(u_len, v_len);
    return patch;
  };

  // The first patch centred on saddle point i, if any.
  std::vector<std::pair<double, int>> near;
  auto patch_at = [&](int i) -> std::optional<GridPatch> {
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

    for (const auto& [du2, q] : near) {
      // p + u: a neighbour along one grid line, so of opposite sign...
      if (!(-HessianCosine(p, saddles[q]) >= options.min_cosine)) continue;
      const cv::Point2d u = At(saddles[q]) - At(p);
      const double u_len = std::sqrt(du2);
      // ... and p - u on the other side.
      const int back = nearest(At(p) - u, options.tolerance * u_len + options.slack_px, p, -1, {});
      if (back < 0) continue;
      for (const auto& [dv2, s] : near) {
        // p + v: a neighbour along the other grid line.
        if (s == q || s == back || !(-HessianCosine(p, saddles[s]) >= options.min_cosine)) continue;
        const cv::Point2d v = At(saddles[s]) - At(p);
        const double v_len = std::sqrt(dv2);
        if (std::abs(u.x * v.y - u.y * v.x) < options.min_sine * u_len * v_len) continue;
        // The diagonal neighbours p ± u + v have p's sign.
        const double tol = options.tolerance * std::min(u_len, v_len) + options.slack_px;
        const int q_v = nearest(At(saddles[q]) + v, tol, p, +1, {});
        if (q_v < 0) continue;
        const int back_v = nearest(At(saddles[back]) + v, tol, p, +1, {});
        if (back_v < 0) continue;
        if (options.rows == 2) return patch_of({back, i, q, back_v, s, q_v}, u_len, v_len);
        // Three rows: p - v, of the other sign, and p ± u - v, of p's.
        const int below =
            nearest(At(p) - v, options.tolerance * v_len + options.slack_px, p, -1, {q, back});
        if (below < 0) continue;
        const cv::Point2d w = At(saddles[below]) - At(p);
        const int q_w = nearest(At(saddles[q]) + w, tol, p, +1, {});
        const int back_w = q_w < 0 ? -1 : nearest(At(saddles[back]) + w, tol, p, +1, {});
        if (back_w >= 0)
          return patch_of({back_w, below, q_w, back, i, q, back_v, s, q_v}, u_len, v_len);
      }
    }
    return std::nullopt;
  };

  for (int i = 0; i < static_cast<int>(saddles.size()) && patches.size() < max_patches; ++i)
    if (auto patch = patch_at(i)) patches.push_back(std::move(*patch));
  return patches;
}

std::vector<Lattice> GrowLattices(const std::vector<SaddlePoint>& all_saddles,
                                  const std::vector<GridPatch>& patches,
                                  const GridPatchOptions& options, std::size_t max_points) {
  std::vector<Lattice> lattices;
  const std::vector<SaddlePoint> saddles = XJunctions(all_saddles, options);
  if (saddles.empty()) return lattices;
  const PointIndex index(saddles, kCellPx);
  // The lattice (its number) each saddle point was last made part of; -1
  // for none. A patch whose centre is part of a lattice grown before grows
  // no other.
  std::vector<int> owner(saddles.size(), -1);
  auto index_of = [&](const cv::Point& pixel) {
    int found = -1;
    index.ForEachWithin(cv::Point2d(pixel.x, pixel.y), 0.5, [&](int j, double) { found = j; });
    return found;
  };
  using Node = std::pair<int, int>;  // (a, b): along the patch's first direction, its second
  int number = 0;
  for (const GridPatch& patch : patches) {
    const int patch_rows = static_cast<int>(patch.corners.size()) / 3;
    if (patch_rows < 2) continue;
    const int centre = index_of(patch.corners[patch_rows == 3 ? 4 : 1]);
    if (centre < 0 || owner[centre] >= 0) continue;
    ++number;
    std::map<Node, int> at;
    for (int k = 0; k < static_cast<int>(patch.corners.size()); ++k) {
      const int j = index_of(patch.corners[k]);
      if (j < 0 || owner[j] == number) break;
      at[{k % 3, k / 3}] = j;
      owner[j] = number;
    }
    if (at.size() != patch.corners.size()) continue;
    // Grown breadth first: the next corner along a grid line is where the
    // last step predicts it, within the patches' tolerance, and of the
    // opposite Hessian sign (the squares' colours swap).
    std::deque<Node> open(at.size());
    std::transform(at.begin(), at.end(), open.begin(),
                   [](const auto& entry) { return entry.first; });
    bool too_large = false;
    while (!open.empty() && !too_large) {
      const auto [a, b] = open.front();
      open.pop_front();
      for (const auto& [da, db] : {Node{1, 0}, Node{-1, 0}, Node{0, 1}, Node{0, -1}}) {
        if (at.count({a + da, b + db})) continue;
        const auto behind = at.find({a - da, b - db});
        if (behind == at.end()) continue;
        const SaddlePoint& p = saddles[at.at({a, b})];
        const cv::Point2d step = At(p) - At(saddles[behind->second]);
        const double radius = options.tolerance * cv::norm(step) + options.slack_px;
        int best = -1;
        double best_d2 = radius * radius;
        index.ForEachWithin(At(p) + step, radius, [&](int j, double d2) {
          if (d2 <= best_d2 && owner[j] != number &&
              -HessianCosine(p, saddles[j]) >= options.min_cosine)
            best = j, best_d2 = d2;
        });
        if (best < 0) continue;
        at[{a + da, b + db}] = best;
        owner[best] = number;
        open.emplace_back(a + da, b + db);
        if (at.size() > max_points) too_large = true;
      }
    }
    if (too_large) continue;
    int a0 = 0, a1 = 0, b0 = 0, b1 = 0;
    for (const auto& [node, j] : at) {
      a0 = std::min(a0, node.first), a1 = std::max(a1, node.first);
      b0 = std::min(b0, node.second), b1 = std::max(b1, node.second);
    }
    Lattice lattice;
    lattice.cols = a1 - a0 + 1;
    lattice.rows = b1 - b0 + 1;
    // A lattice grown along a few long lines would span a large, empty box.
    if (static_cast<std::size_t>(lattice.cols) * lattice.rows > 4 * max_points) continue;
    lattice.points.resize(static_cast<std::size_t>(lattice.cols) * lattice.rows);
    lattice.found.resize(lattice.points.size(), 0);
    for (const auto& [node, j] : at) {
      const std::size_t k =
          static_cast<std::size_t>(node.second - b0) * lattice.cols + (node.first - a0);
      lattice.points[k] = saddles[j].pixel;
      lattice.found[k] = 1;
    }
    lattices.push_back(std::move(lattice));
  }
  return lattices;
}

bool HasGridPatch(const std::vector<SaddlePoint>& saddles, const GridPatchOptions& options) {
  return !FindGridPatches(saddles, options, 1).empty();
}

bool MayShowCornerGrid(const cv::Mat& gray, int rows) {
  if (std::min(gray.cols, gray.rows) / 2 < kMinLevelSide) return true;
  GridPatchOptions options;
  options.rows = rows;
  return HasGridPatch(FindSaddlePoints(BlockMean(gray, 2), SaddleRegionOptions{}), options);
}

}  // namespace handeye::internal
