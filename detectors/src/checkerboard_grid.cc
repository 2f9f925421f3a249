// SPDX-License-Identifier: GPL-2.0-or-later
#include "checkerboard_grid.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "corner_refinement.h"

namespace handeye::internal {

/// True when the image around `c` looks like a checkerboard X-junction: on a
/// ring inside the four squares it is point-symmetric (two dark sectors
/// opposite each other), so its first angular harmonic is small against the
/// second. The end of a black square against the white margin (an L or T
/// junction, which findChessboardCornersSB can mistake for a corner) has a
/// first harmonic larger than its second.
bool LooksLikeXJunction(const cv::Mat& gray, const cv::Point2d& c, double radius) {
  constexpr int kSamples = 48;
  std::complex<double> h1(0, 0), h2(0, 0);
  for (int k = 0; k < kSamples; ++k) {
    const double theta = 2 * M_PI * k / kSamples;
    const double value =
        Bilinear(gray, c.x + radius * std::cos(theta), c.y + radius * std::sin(theta));
    h1 += value * std::polar(1.0, -theta);
    h2 += value * std::polar(1.0, -2 * theta);
  }
  return std::abs(h1) < 0.5 * std::abs(h2);
}

namespace {

/// Distance (px) from grid point (a, b) to the nearest grid line that does
/// not pass through it: the largest window whose edges all point at this
/// corner. For each pair of neighbours along the two grid directions, steps u
/// and v span a cell; the lines through the neighbours, parallel to the other
/// direction, are the cell's heights |u x v| / |v| and |u x v| / |u| away. On
/// a square seen head-on that is the side; on a board seen obliquely (cells
/// sheared to 40-60 degrees) it is much less than the distance to the nearest
/// corner, which let the window take in a parallel edge and pulled the
/// estimate off by pixels.
double NearestLineDistance(const Grid& grid, int a, int b) {
  double nearest = std::numeric_limits<double>::infinity();
  const cv::Point2d p = grid.At(a, b);
  for (const int da : {-1, 1}) {
    if (a + da < 0 || a + da >= grid.cols) continue;
    const cv::Point2d u = grid.At(a + da, b) - p;
    for (const int db : {-1, 1}) {
      if (b + db < 0 || b + db >= grid.rows) continue;
      const cv::Point2d v = grid.At(a, b + db) - p;
      const double area = std::abs(u.x * v.y - u.y * v.x);
      nearest = std::min(
          {nearest, area / std::max(cv::norm(u), 1e-9), area / std::max(cv::norm(v), 1e-9)});
    }
  }
  return nearest;
}

/// Refinement window radius as a fraction of the distance to the nearest grid
/// line not through the corner (NearestLineDistance; on squares seen head-on,
/// the distance to the nearest corner), and its bounds in pixels. Measured on
/// rendered boards seen nearly head-on (10-60 px squares, blur 0.5-1 px, noise
/// 2 grey levels): 0.7 beat 0.4-0.6 for small squares (the neighbours' edges
/// on the same grid lines still point at this corner, and the Gaussian weight
/// fades the others), and larger windows stop helping past about 25 px.
constexpr double kWindowFraction = 0.7;
constexpr double kMinRadiusPx = 2.0;
constexpr double kMaxRadiusPx = 25.0;

/// Largest distance of a refined corner from where the homography fitted to
/// the other corners of its 3x3 neighbourhood puts it, as a fraction of the
/// mean side of the squares there. Corners of one board lie where a plane seen
/// in perspective puts them, so each is predicted by its neighbours to within
/// their noise plus the lens distortion over two squares: at most 0.008 of a
/// square on METRIC's synthetic medium cell rendered by default (358 views),
/// 0.04 with blur 1.5 px and noise 8 grey levels (1763 views). The two grids
/// that passed every other check there were off by 14 and 140 px and
/// predicted 0.52 and 1.48 of a square off: the sector detector had put one
/// corner on the long edge of an oblique black square, or skipped a row of the
/// board and taken the last one from a thin dark line in the clutter below,
/// and both look enough like X-junctions to survive refinement. Each corner is
/// left out of the fit that judges it: a homography fitted to all nine absorbs
/// most of one corner's error (with the 14 px corner, no residual exceeded
/// 0.11 of a square).
constexpr double kMaxPerspectiveError = 0.15;

/// True when every corner of every block of 3x3 grid points (2x3 or 3x2 on a
/// board with two points a side) is within
/// kMaxPerspectiveError of a square of where the homography from the board's
/// square grid fitted to the block's other corners puts it. Blocks rather
/// than the whole board, so that lens distortion, which bends the grid over
/// the whole board, stays far below the tolerance.
bool FitsPerspective(const Grid& grid) {
  const int wa = std::min(grid.cols, 3), wb = std::min(grid.rows, 3);
  // Four points determine a homography: a left-out corner needs four others,
  // and a fit to only four of them has no redundancy to judge by.
  if (wa * wb < 6) return true;
  const int n = wa * wb;
  std::vector<Eigen::Vector2d> board, seen(n);
  for (int b = 0; b < wb; ++b)
    for (int a = 0; a < wa; ++a) board.emplace_back(a, b);
  std::vector<Eigen::Vector2d> board_others(n - 1), seen_others(n - 1);
  for (int b0 = 0; b0 + wb <= grid.rows; ++b0) {
    for (int a0 = 0; a0 + wa <= grid.cols; ++a0) {
      double side_sum = 0;
      int sides = 0;
      for (int b = 0; b < wb; ++b) {
        for (int a = 0; a < wa; ++a) {
          const cv::Point2d p = grid.At(a0 + a, b0 + b);
          seen[b * wa + a] = Eigen::Vector2d(p.x, p.y);
          if (a + 1 < wa) side_sum += cv::norm(grid.At(a0 + a + 1, b0 + b) - p), ++sides;
          if (b + 1 < wb) side_sum += cv::norm(grid.At(a0 + a, b0 + b + 1) - p), ++sides;
        }
      }
      const double tolerance = kMaxPerspectiveError * side_sum / sides;
      for (int k = 0; k < n; ++k) {
        for (int m = 0, o = 0; m < n; ++m) {
          if (m == k) continue;
          board_others[o] = board[m];
          seen_others[o++] = seen[m];
        }
        // Plain least squares: a wrong corner among the others must show as
        // an error, not be voted away.
        const std::optional<Eigen::Matrix3d> H = FitHomographyFast(board_others, seen_others);
        if (!H) return false;
        if (!((ApplyHomography(*H, board[k]) - seen[k]).norm() <= tolerance)) return false;
      }
    }
  }
  return true;
}

}  // namespace

/// Refines every corner of the grid in place; false if one fails or does
/// not look like a checkerboard corner, or if together they are not where
/// a plane seen in perspective would put them (FitsPerspective).
bool RefineGrid(const cv::Mat& gray, Grid* grid) {
  // Gradients only over the board's bounding box plus the largest window.
  cv::Rect box = cv::boundingRect(grid->px);
  const int pad = static_cast<int>(kMaxRadiusPx) + 3;
  box = cv::Rect(box.x - pad, box.y - pad, box.width + 2 * pad, box.height + 2 * pad) &
        cv::Rect(0, 0, gray.cols, gray.rows);
  if (box.area() == 0) return false;
  const Gradients gradients = SobelGradients(gray, box);
  // Each window's size follows from the grid's shape (NearestLineDistance).
  // Sized from the grid the search returned, which is off by up to a pixel or
  // so, the refined corners depended on where the search had looked: 0.06 px
  // between a crop and the whole image on METRIC. Sized again from the
  // refined grid, a second pass leaves only that grid's own error.
  std::vector<cv::Point2f> refined(grid->px.size());
  Grid shape = *grid;
  for (int pass = 0; pass < 2; ++pass) {
    for (int b = 0; b < grid->rows; ++b) {
      for (int a = 0; a < grid->cols; ++a) {
        const double radius = std::clamp(kWindowFraction * NearestLineDistance(shape, a, b),
                                         kMinRadiusPx, kMaxRadiusPx);
        const cv::Point2d guess = shape.At(a, b);
        // A corner that runs half a window away was no corner.
        const auto refined_px = RefineXCorner(gradients, Eigen::Vector2d(guess.x, guess.y),
                                              radius * Eigen::Matrix2d::Identity(), 0.5 * radius);
        if (!refined_px) return false;
        const cv::Point2d corner(refined_px->x(), refined_px->y());
        if (!LooksLikeXJunction(gray, corner, 0.5 * radius)) return false;
        refined[static_cast<size_t>(b) * grid->cols + a] =
            cv::Point2f(static_cast<float>(corner.x), static_cast<float>(corner.y));
      }
    }
    shape.px = refined;
  }
  Grid refined_grid = *grid;
  refined_grid.px = std::move(refined);
  if (!FitsPerspective(refined_grid)) return false;
  *grid = std::move(refined_grid);
  return true;
}

bool OneLineOff(const cv::Mat& gray, const Grid& grid) {
  if (grid.cols < 3 || grid.rows < 3) return true;
  // Each side in turn: the lines kept are [a0, a0 + cols) x [b0, b0 + rows).
  const int sides[4][4] = {{1, 0, grid.cols - 1, grid.rows},
                           {0, 0, grid.cols - 1, grid.rows},
                           {0, 1, grid.cols, grid.rows - 1},
                           {0, 0, grid.cols, grid.rows - 1}};
  for (const auto& [a0, b0, cols, rows] : sides) {
    Grid rest;
    rest.cols = cols;
    rest.rows = rows;
    for (int b = 0; b < rows; ++b)
      for (int a = 0; a < cols; ++a)
        rest.px.push_back(grid.px[static_cast<std::size_t>(b0 + b) * grid.cols + a0 + a]);
    if (RefineGrid(gray, &rest)) return true;
  }
  return false;
}

/// Median distance (px) between grid neighbours: the size of a square. The
/// median, as a wrong grid may join a few corners of clutter far apart.
double MedianSquare(const Grid& grid) {
  std::vector<double> sides;
  for (int b = 0; b < grid.rows; ++b) {
    for (int a = 0; a < grid.cols; ++a) {
      if (a + 1 < grid.cols) sides.push_back(cv::norm(grid.At(a + 1, b) - grid.At(a, b)));
      if (b + 1 < grid.rows) sides.push_back(cv::norm(grid.At(a, b + 1) - grid.At(a, b)));
    }
  }
  std::nth_element(sides.begin(), sides.begin() + sides.size() / 2, sides.end());
  return sides[sides.size() / 2];
}

}  // namespace handeye::internal
