// SPDX-License-Identifier: GPL-2.0-or-later
#include "charuco_squares.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <queue>
#include <tuple>
#include <utility>

#include "corner_refinement.h"

namespace handeye::internal {
namespace {

/// Two squares touch where a corner of each lies within this share of the
/// smaller square's mean side of the other's: the threshold that makes the
/// quadrilaterals leaves a gap of a pixel or two between black squares that
/// meet at a corner, and a square's own other corners are a side away.
constexpr double kTouchShare = 0.5;
/// And the two squares lie on opposite sides of the corner they share: the
/// directions from their centres to it at least this far from alike (cos).
constexpr double kOppositeCos = -0.7;
/// Quadrilaterals smaller than this (px²) are noise, not squares.
constexpr double kMinQuadAreaPx = 12.0;
/// Fewest black squares joined before a lattice is placed: fewer leave too
/// few markers between them to tell the placements apart.
constexpr int kMinSquares = 4;
/// Lattice points within this many squares of a marker's (or a corner's)
/// along each board axis give its local homography: near points only, so
/// that lens distortion across the board does not bend it.
constexpr double kLocalSquares = 1.6;
/// A placement numbers the board when the markers' grey levels follow its
/// print with at least this correlation and clearly better than under any
/// other placement.
constexpr double kMinCorrelation = 0.3;
/// Markers OpenCV decoded that must lie where a placement puts them for each
/// one that does not (a misread) before the placement is tried.
constexpr int kMinAgreeingPerMisread = 3;
/// Bits sampled before a placement is judged: two markers' worth at least.
constexpr int kMinBitsPerPlacement = 2;

struct Quad {
  std::array<Eigen::Vector2d, 4> corner;  ///< clockwise in the image (y down)
  Eigen::Vector2d centre;
  double side = 0;  ///< mean side length, px
};

/// A corner's offset within its square, in lattice units, by the corner's
/// direction: 0 top left, 1 top right, 2 bottom right, 3 bottom left.
const std::array<Eigen::Vector2i, 4> kCornerOffset = {Eigen::Vector2i(0, 0), Eigen::Vector2i(1, 0),
                                                      Eigen::Vector2i(1, 1), Eigen::Vector2i(0, 1)};

std::vector<Quad> CleanQuads(const std::vector<std::vector<cv::Point2f>>& quads) {
  std::vector<Quad> clean;
  for (const auto& q : quads) {
    if (q.size() != 4) continue;
    Quad quad;
    double twice_area = 0;
    for (int k = 0; k < 4; ++k) {
      quad.corner[k] = Eigen::Vector2d(q[k].x, q[k].y);
      const auto& n = q[(k + 1) % 4];
      twice_area += q[k].x * n.y - n.x * q[k].y;
    }
    if (std::abs(twice_area) < 2 * kMinQuadAreaPx) continue;
    // Clockwise on screen, as the board's top left, top right, bottom right,
    // bottom left are when it is seen from the front.
    if (twice_area < 0) std::swap(quad.corner[1], quad.corner[3]);
    quad.centre = Eigen::Vector2d::Zero();
    for (int k = 0; k < 4; ++k) {
      quad.centre += quad.corner[k] / 4.0;
      quad.side += (quad.corner[(k + 1) % 4] - quad.corner[k]).norm() / 4.0;
    }
    clean.push_back(quad);
  }
  return clean;
}

/// Where a square touches another at one of its corners (the index of the
/// corner holding it): the other square, its corner there, and the gap.
struct Touch {
  int other = -1;
  int other_corner = -1;
  double gap_px = 0;
};

/// Per square and corner, the square touching it there (mutually nearest).
std::vector<std::array<Touch, 4>> FindTouches(const std::vector<Quad>& quads) {
  const std::size_t n = quads.size();
  std::vector<std::array<Touch, 4>> nearest(n);
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b) {
      if (a == b) continue;
      const double reach = kTouchShare * std::min(quads[a].side, quads[b].side);
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          const double gap = (quads[a].corner[i] - quads[b].corner[j]).norm();
          if (gap > reach) continue;
          const Eigen::Vector2d out_a = (quads[a].corner[i] - quads[a].centre).normalized();
          const Eigen::Vector2d out_b = (quads[b].corner[j] - quads[b].centre).normalized();
          if (out_a.dot(out_b) > kOppositeCos) continue;
          Touch& t = nearest[a][i];
          if (t.other < 0 || gap < t.gap_px) t = {static_cast<int>(b), j, gap};
        }
    }
  // Mutual only.
  for (std::size_t a = 0; a < n; ++a)
    for (int i = 0; i < 4; ++i) {
      const Touch& t = nearest[a][i];
      if (t.other < 0) continue;
      const Touch& back = nearest[t.other][t.other_corner];
      if (back.other != static_cast<int>(a) || back.other_corner != i) nearest[a][i] = Touch();
    }
  return nearest;
}

using Point = std::pair<int, int>;

/// The black squares joined into one lattice: each square's top-left point
/// (in squares, up to a turn and shift of the whole) and its corners in the
/// image, top left, top right, bottom right, bottom left in the lattice.
struct Lattice {
  std::vector<Point> squares;
  std::vector<std::array<Eigen::Vector2d, 4>> corners;
};

/// The largest set of squares joined corner to corner, numbered from one of
/// them: joins taken closest gap first (relative to the squares' size), a
/// join that contradicts the numbering so far (a clutter quad, two black
/// squares read as one) left out.
std::optional<Lattice> JoinSquares(const std::vector<Quad>& quads,
                                   const std::vector<std::array<Touch, 4>>& touches) {
  const int n = static_cast<int>(quads.size());
  Lattice best;
  std::vector<bool> used(n, false);
  for (int seed = 0; seed < n; ++seed) {
    if (used[seed]) continue;
    // Each square's lattice position and the image corner that is its top left.
    std::vector<std::optional<std::pair<Point, int>>> placed(n);
    std::map<Point, int> at;
    placed[seed] = std::make_pair(Point(0, 0), 0);
    at[Point(0, 0)] = seed;
    using Join = std::tuple<double, int, int>;  // relative gap, square, its corner
    std::priority_queue<Join, std::vector<Join>, std::greater<Join>> open;
    const auto offer = [&](int a) {
      for (int i = 0; i < 4; ++i)
        if (touches[a][i].other >= 0 && !placed[touches[a][i].other])
          open.emplace(
              touches[a][i].gap_px / std::min(quads[a].side, quads[touches[a][i].other].side), a,
              i);
    };
    offer(seed);
    while (!open.empty()) {
      const auto [gap, a, i] = open.top();
      open.pop();
      const Touch& t = touches[a][i];
      if (placed[t.other]) continue;
      const auto [pos, first] = *placed[a];
      const int direction = (i - first + 4) % 4;
      // The square across corner `direction` lies one square diagonally
      // away, and touches it with its opposite corner.
      const Eigen::Vector2i step = 2 * kCornerOffset[direction] - Eigen::Vector2i(1, 1);
      const Point other_pos(pos.first + step.x(), pos.second + step.y());
      if (at.count(other_pos)) continue;
      placed[t.other] = std::make_pair(other_pos, (t.other_corner - (direction + 2) % 4 + 4) % 4);
      at[other_pos] = t.other;
      offer(t.other);
    }
    for (const auto& [pos, a] : at) used[a] = true;
    if (static_cast<int>(at.size()) <= static_cast<int>(best.squares.size())) continue;
    best = Lattice();
    for (const auto& [pos, a] : at) {
      const int first = placed[a]->second;
      std::array<Eigen::Vector2d, 4> corners;
      for (int i = 0; i < 4; ++i) corners[(i - first + 4) % 4] = quads[a].corner[i];
      best.squares.push_back(pos);
      best.corners.push_back(corners);
    }
  }
  if (static_cast<int>(best.squares.size()) < kMinSquares) return std::nullopt;
  return best;
}

/// A placement of the lattice on the board: board point (squares) =
/// Turn(lattice point) + shift, and the image of each board point that the
/// squares landing on black squares show (a point two of them share lies in
/// the gap between their quadrilaterals: their mean).
struct Placement {
  int turn = 0;  ///< quarter turns
  Eigen::Vector2i shift = Eigen::Vector2i::Zero();
  std::map<Point, Eigen::Vector2d> points;
  int misfits = 0;  ///< squares of the lattice that land on no black square

  Eigen::Vector2i Turn(const Point& p) const {
    const Eigen::Vector2i q(p.first, p.second);
    switch (turn) {
      case 1:
        return {-q.y(), q.x()};
      case 2:
        return {-q.x(), -q.y()};
      case 3:
        return {q.y(), -q.x()};
      default:
        return q;
    }
  }
};

/// Every placement under which the squares of the lattice land on black
/// squares of the board, but for one in six at most (quads of clutter
/// joined to the board's).
std::vector<Placement> Placements(const CharucoTarget& target, const Lattice& lattice) {
  const int squares = static_cast<int>(lattice.squares.size());
  const int allowed_misfits = squares / 6;
  std::vector<Placement> placements;
  for (int turn = 0; turn < 4; ++turn) {
    Placement p;
    p.turn = turn;
    // Each square's smallest corner once turned, and their range.
    std::vector<Eigen::Vector2i> low;
    Eigen::Vector2i lo = Eigen::Vector2i::Constant(1 << 20), hi = -lo;
    for (const Point& s : lattice.squares) {
      Eigen::Vector2i m = p.Turn(s);
      for (const auto& o : kCornerOffset)
        m = m.cwiseMin(p.Turn(Point(s.first + o.x(), s.second + o.y())));
      low.push_back(m);
      lo = lo.cwiseMin(m);
      hi = hi.cwiseMax(m);
    }
    const auto black = [&target](const Eigen::Vector2i& a) {
      return a.x() >= 0 && a.y() >= 0 && a.x() < target.squares_x() && a.y() < target.squares_y() &&
             target.MarkerInSquare(a.x(), a.y()) < 0;
    };
    for (int sx = -hi.x(); sx + lo.x() < target.squares_x(); ++sx)
      for (int sy = -hi.y(); sy + lo.y() < target.squares_y(); ++sy) {
        p.shift = Eigen::Vector2i(sx, sy);
        int misfits = 0;
        for (const auto& m : low) misfits += black(m + p.shift) ? 0 : 1;
        if (misfits > allowed_misfits) continue;
        p.misfits = misfits;
        std::map<Point, std::vector<Eigen::Vector2d>> seen;
        for (int k = 0; k < squares; ++k) {
          if (!black(low[k] + p.shift)) continue;
          for (int d = 0; d < 4; ++d) {
            const Point& s = lattice.squares[k];
            const Eigen::Vector2i q =
                p.Turn(Point(s.first + kCornerOffset[d].x(), s.second + kCornerOffset[d].y())) +
                p.shift;
            seen[Point(q.x(), q.y())].push_back(lattice.corners[k][d]);
          }
        }
        p.points.clear();
        for (const auto& [q, uvs] : seen) {
          Eigen::Vector2d mean = Eigen::Vector2d::Zero();
          for (const auto& uv : uvs) mean += uv / static_cast<double>(uvs.size());
          p.points[q] = mean;
        }
        placements.push_back(p);
      }
  }
  return placements;
}

/// The homography (board metres to pixels) of the points of `placement`
/// within kLocalSquares of `centre` (board metres), by FitHomographyFast:
/// every placement of every view is scored with one per marker, and an SVD
/// of the whole system (FitHomography) cost 15 % of the detection of a view
/// with no board.
std::optional<Eigen::Matrix3d> LocalHomography(const Placement& placement, double L,
                                               const Eigen::Vector2d& centre) {
  std::vector<Eigen::Vector2d> board, image;
  for (const auto& [q, uv] : placement.points) {
    const Eigen::Vector2d xy = Eigen::Vector2d(q.first, q.second) * L;
    if (((xy - centre).cwiseAbs() / L).maxCoeff() > kLocalSquares) continue;
    board.push_back(xy);
    image.push_back(uv);
  }
  return FitHomographyFast(board, image);
}

/// Correlation of the image's grey levels at the centres of the markers'
/// bits with the print's, under `placement`; nullopt with too few bits seen.
std::optional<double> PrintCorrelation(const CharucoTarget& target, const cv::Mat& gray,
                                       const Placement& placement) {
  const double L = target.square_size_m();
  const int bits = target.dictionary().bits;
  std::vector<double> seen, printed;
  for (int m = 0; m < target.NumMarkers(); ++m) {
    const auto corners = target.MarkerCorners(m);
    const Eigen::Vector2d c0 = corners[0].head<2>(), c2 = corners[2].head<2>();
    const auto H = LocalHomography(placement, L, (c0 + c2) / 2);
    if (!H) continue;
    const Eigen::Vector2d cell = (c2 - c0) / (bits + 2);
    for (int r = 1; r <= bits; ++r)
      for (int c = 1; c <= bits; ++c) {
        const Eigen::Vector2d xy = c0 + Eigen::Vector2d((c + 0.5) * cell.x(), (r + 0.5) * cell.y());
        const Eigen::Vector2d uv = ApplyHomography(*H, xy);
        if (!(uv.x() >= 0 && uv.y() >= 0 && uv.x() < gray.cols - 1 && uv.y() < gray.rows - 1))
          continue;
        seen.push_back(Bilinear(gray, uv.x(), uv.y()));
        printed.push_back(target.Albedo(xy.x(), xy.y()));
      }
  }
  if (seen.size() < static_cast<std::size_t>(kMinBitsPerPlacement * bits * bits))
    return std::nullopt;
  return Pearson(seen, printed);
}

/// The decoded markers whose square's four corners `placement` shows: how
/// many lie where the placement puts their print (centre within half a
/// square) and how many do not. (Beyond the points seen a homography would
/// extrapolate.)
std::pair<int, int> DecodedMarkersFit(const CharucoTarget& target, const Placement& placement,
                                      const std::vector<int>& marker_ids,
                                      const std::vector<std::vector<cv::Point2f>>& marker_corners) {
  const double L = target.square_size_m();
  int agree = 0, disagree = 0;
  for (std::size_t i = 0; i < marker_ids.size(); ++i) {
    const auto corners = target.MarkerCorners(marker_ids[i]);
    const Eigen::Vector2d centre = (corners[0].head<2>() + corners[2].head<2>()) / 2;
    const int a = static_cast<int>(std::floor(centre.x() / L));
    const int b = static_cast<int>(std::floor(centre.y() / L));
    std::vector<Eigen::Vector2d> board, image;
    for (const auto& o : kCornerOffset) {
      const auto it = placement.points.find(Point(a + o.x(), b + o.y()));
      if (it == placement.points.end()) break;
      board.push_back(Eigen::Vector2d(a + o.x(), b + o.y()) * L);
      image.push_back(it->second);
    }
    const auto H = FitHomography(board, image);
    if (!H) continue;
    Eigen::Vector2d seen = Eigen::Vector2d::Zero();
    for (const auto& c : marker_corners[i]) seen += Eigen::Vector2d(c.x, c.y) / 4.0;
    ((ApplyHomography(H->inverse(), seen) - centre).norm() <= 0.5 * L ? agree : disagree) += 1;
  }
  return {agree, disagree};
}

}  // namespace

SquaresPlacement PlaceCornersBySquares(
    const CharucoTarget& target, const cv::Mat& gray,
    const std::vector<std::vector<cv::Point2f>>& quads, const std::vector<int>& marker_ids,
    const std::vector<std::vector<cv::Point2f>>& marker_corners) {
  SquaresPlacement placed;
  const std::vector<Quad> clean = CleanQuads(quads);
  const auto lattice = JoinSquares(clean, FindTouches(clean));
  if (!lattice) return placed;

  const std::vector<Placement> candidates = Placements(target, *lattice);
  std::optional<Placement> best;
  double best_score = -1, second_score = -1;
  for (const Placement& p : candidates) {
    // A marker OpenCV misread may disagree, when three others agree.
    const auto [agree, disagree] = DecodedMarkersFit(target, p, marker_ids, marker_corners);
    if (disagree > 0 && disagree * kMinAgreeingPerMisread > agree) continue;
    const auto score = PrintCorrelation(target, gray, p);
    if (!score) continue;
    if (*score > best_score) {
      second_score = best_score;
      best_score = *score;
      best = p;
    } else {
      second_score = std::max(second_score, *score);
    }
  }
  placed.correlation = best_score;
  if (best) placed.misfits = best->misfits;
  if (!best || best_score < kMinCorrelation || best_score - second_score < kMinLead) return placed;

  const double L = target.square_size_m();
  const int cols = target.squares_x() - 1;
  for (const TargetPoint& point : target.Points()) {
    const int x = point.id % cols + 1, y = point.id / cols + 1;
    const auto it = best->points.find(Point(x, y));
    if (it == best->points.end()) continue;
    const auto H = LocalHomography(*best, L, point.p_target.head<2>());
    if (!H) continue;
    placed.corners.push_back({point.id, it->second, *H});
  }
  return placed;
}

}  // namespace handeye::internal
