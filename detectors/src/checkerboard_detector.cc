// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/detectors/checkerboard_detector.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>

#include "checkerboard_grid.h"
#include "checkerboard_search.h"
#include "corner_refinement.h"

namespace handeye {
namespace {

using internal::Bilinear;
using internal::Grid;

/// Mean grey level over the middle of the quadrilateral q0 q1 q2 q3 (in order
/// around it), sampled bilinearly; NaN when that part is outside the image.
double MeanInside(const cv::Mat& gray, const cv::Point2d& q0, const cv::Point2d& q1,
                  const cv::Point2d& q2, const cv::Point2d& q3) {
  double sum = 0;
  int count = 0;
  for (double s = 0.3; s < 0.71; s += 0.1) {
    for (double t = 0.3; t < 0.71; t += 0.1) {
      const cv::Point2d p = (1 - t) * ((1 - s) * q0 + s * q1) + t * ((1 - s) * q3 + s * q2);
      if (p.x < 0 || p.y < 0 || p.x > gray.cols - 1 || p.y > gray.rows - 1) continue;
      sum += Bilinear(gray, p.x, p.y);
      ++count;
    }
  }
  return count ? sum / count : std::nan("");
}

/// Parity (a + b) % 2 of the grid cells that are black, or nullopt when the
/// two parities do not differ in grey level. Cell (a, b) is the square with
/// corners (a, b) and (a + 1, b + 1); a = -1 or cols - 1 (and the same for b)
/// are the outer squares, found by extrapolating one square out. All inner
/// cells vote (each class mean averages many squares, so shading, noise or a
/// stray reflection on one square cannot flip it); tiny boards with a single
/// inner cell add the outer ring.
std::optional<int> BlackParity(const cv::Mat& gray, const Grid& g) {
  auto point = [&g](int a, int b) {
    // Linear extrapolation one step past the grid on either side.
    const int ca = std::clamp(a, 0, g.cols - 1), cb = std::clamp(b, 0, g.rows - 1);
    cv::Point2d p = g.At(ca, cb);
    if (a != ca) p += (a - ca) * (g.At(ca, cb) - g.At(ca - (a - ca), cb));
    if (b != cb) p += (b - cb) * (g.At(ca, cb) - g.At(ca, cb - (b - cb)));
    return p;
  };
  auto class_means = [&](bool outer) {
    std::array<double, 2> sum{0, 0};
    std::array<int, 2> count{0, 0};
    const int lo = outer ? -1 : 0;
    for (int b = lo; b < g.rows - 1 + (outer ? 1 : 0); ++b) {
      for (int a = lo; a < g.cols - 1 + (outer ? 1 : 0); ++a) {
        const double m =
            MeanInside(gray, point(a, b), point(a + 1, b), point(a + 1, b + 1), point(a, b + 1));
        if (std::isnan(m)) continue;
        const int parity = ((a + b) % 2 + 2) % 2;
        sum[parity] += m;
        ++count[parity];
      }
    }
    return std::array<double, 3>{count[0] ? sum[0] / count[0] : std::nan(""),
                                 count[1] ? sum[1] / count[1] : std::nan(""),
                                 static_cast<double>(std::min(count[0], count[1]))};
  };
  auto means = class_means(false);
  if (means[2] < 1) means = class_means(true);
  // A detected board has black and white squares; without a clear difference
  // the colours (and so the ids) would be a coin toss.
  constexpr double kMinContrast = 5.0;  // grey levels
  if (!(std::abs(means[0] - means[1]) >= kMinContrast)) return std::nullopt;
  return means[0] < means[1] ? 0 : 1;
}

/// A numbering of a grid's points as the corners of a board: target corner
/// (i, j) is grid point (m0 + m1 i + m2 j, m3 + m4 i + m5 j).
using Map = std::array<int, 6>;

cv::Point2d GridPoint(const Grid& grid, const Map& m, int i, int j) {
  return grid.At(m[0] + m[1] * i + m[2] * j, m[3] + m[4] * i + m[5] * j);
}

/// The numbering of `grid` as a board of `cols` x `rows` inner corners that
/// SPEC §4 gives: the printed face's handedness and the black square at
/// corner (0, 0), whose parity among the grid's cells is `black_parity`
/// (BlackParity); nullopt when none fits. A board of the grid's own size is
/// numbered along its axes, a board of the transposed size (or a square one)
/// across them.
std::optional<Map> BestMap(const Grid& grid, int cols, int rows, int black_parity) {
  std::vector<Map> maps;
  const int a_end = grid.cols - 1, b_end = grid.rows - 1;
  if (cols == grid.cols && rows == grid.rows)
    maps = {{0, 1, 0, 0, 0, 1},
            {a_end, -1, 0, b_end, 0, -1},
            {a_end, -1, 0, 0, 0, 1},
            {0, 1, 0, b_end, 0, -1}};
  if (cols == grid.rows && rows == grid.cols) {
    maps.push_back({0, 0, 1, 0, 1, 0});
    maps.push_back({a_end, 0, -1, 0, 1, 0});
    maps.push_back({0, 0, 1, b_end, -1, 0});
    maps.push_back({a_end, 0, -1, b_end, -1, 0});
  }
  std::optional<Map> best;
  double best_score = -1e9;
  for (const Map& m : maps) {
    // Handedness: the printed face seen from its -z side shows +x then +y
    // turning clockwise on screen (u right, v down), i.e. cross(d_i, d_j) > 0.
    cv::Point2d d_i(0, 0), d_j(0, 0);
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i + 1 < cols; ++i)
        d_i += GridPoint(grid, m, i + 1, j) - GridPoint(grid, m, i, j);
    for (int j = 0; j + 1 < rows; ++j)
      for (int i = 0; i < cols; ++i) d_j += GridPoint(grid, m, i, j + 1) - GridPoint(grid, m, i, j);
    if (d_i.x * d_j.y - d_i.y * d_j.x <= 0) continue;
    // SPEC §4: the square on the -x, -y side of corner (0, 0) is black. It
    // touches (0, 0) diagonally to target square (0, 0), between corners
    // (0, 0) and (1, 1), so both have one colour; square (0, 0) is an inner
    // cell, measured between four detected corners rather than extrapolated.
    const int a0 = m[0], b0 = m[3];
    const int a1 = m[0] + m[1] + m[2], b1 = m[3] + m[4] + m[5];
    const int parity = (std::min(a0, a1) + std::min(b0, b1)) % 2;
    if (parity != black_parity) continue;
    // Boards that look the same turned (cols + rows even) leave several maps;
    // take the one whose i axis points most to the image's right, so views
    // of similar orientation number the board alike.
    const double score = d_i.x / (cv::norm(d_i) + 1e-12);
    if (score > best_score) {
      best_score = score;
      best = m;
    }
  }
  return best;
}

/// OpenCV's random state at the start of every detection.
constexpr std::uint64_t kRandomState = 0x5eed;

}  // namespace

CheckerboardDetector::CheckerboardDetector(std::shared_ptr<const CheckerboardTarget> target)
    : target_(std::move(target)) {
  if (!target_) throw std::invalid_argument("CheckerboardDetector: null target");
}

std::optional<Detection> CheckerboardDetector::Detect(const cv::Mat& gray) const {
  return DetectOrExplain(gray, nullptr);
}

std::optional<Detection> CheckerboardDetector::DetectOrExplain(const cv::Mat& gray,
                                                               std::string* mismatch) const {
  if (mismatch) mismatch->clear();
  if (gray.empty() || gray.type() != CV_8UC1)
    throw std::invalid_argument("CheckerboardDetector: expected an 8-bit single-channel image");
  const int cols = target_->cols(), rows = target_->rows();
  // The sector detector draws from the calling thread's cv::theRNG(), so its
  // corners depended on what that thread had done before (with several
  // detection threads, on which worker took which image): every image starts
  // from the same state, and the caller's state is put back.
  cv::RNG& rng = cv::theRNG();
  const std::uint64_t callers_state = rng.state;
  rng.state = kRandomState;
  auto grid_or_none = internal::FindGrid(gray, cols, rows);
  rng.state = callers_state;
  if (!grid_or_none) return std::nullopt;
  const Grid& grid = *grid_or_none;

  const std::optional<int> black_parity = BlackParity(gray, grid);
  if (!black_parity) return std::nullopt;
  const std::optional<Map> best = BestMap(grid, cols, rows, *black_parity);
  if (!best) {
    // cols and rows both odd: a board of rows x cols inner corners (the same
    // squares turned a quarter) has white squares where the declared one has
    // its black outer corner squares, so it fits no numbering of the declared
    // size. Grids of either orientation are searched, so that board is found.
    if (mismatch && cols != rows && BestMap(grid, rows, cols, *black_parity))
      *mismatch = "the board in the images has " + std::to_string(rows) + "x" +
                  std::to_string(cols) + " inner corners; the target declares inner_corners [" +
                  std::to_string(cols) + ", " + std::to_string(rows) + "]: swap it to [" +
                  std::to_string(rows) + ", " + std::to_string(cols) + "]";
    return std::nullopt;
  }

  Detection detection;
  detection.ids.reserve(cols * rows);
  detection.points_px.reserve(cols * rows);
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < cols; ++i) {
      const cv::Point2d p = GridPoint(grid, *best, i, j);
      detection.ids.push_back(j * cols + i);
      detection.points_px.emplace_back(p.x, p.y);
    }
  }
  return detection;
}

}  // namespace handeye
