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

#include "grid_patch.h"
#include "saddle_regions.h"

namespace handeye {
namespace {

/// Grid of detected corners as OpenCV orders them: point (a, b) at
/// b * cols + a, a in [0, cols), b in [0, rows).
struct Grid {
  int cols = 0, rows = 0;
  std::vector<cv::Point2f> px;
  cv::Point2d At(int a, int b) const { return px[static_cast<size_t>(b) * cols + a]; }
};

/// Grey level at a sub-pixel position (bilinear; clamped at the border).
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

/// Sub-pixel corner by gradient orthogonality on the image's own pixel grid:
/// the gradient on any edge through the corner c is orthogonal to (p - c), so
/// c solves sum_p w(p) g gᵀ (p - c) = 0, iterated with a Gaussian weight
/// centred on the current estimate. Unlike cv::cornerSubPix it does not
/// resample the window at the sub-pixel estimate, which on rendered boards
/// halved the error (0.019 -> 0.010 px for 40 px squares without noise).
/// `gx`, `gy` are 3x3 Sobel gradients of an image region whose top-left pixel
/// is `origin`. Returns false when the estimate runs away (no corner there).
bool RefineCorner(const cv::Mat& gx, const cv::Mat& gy, const cv::Point& origin, double radius,
                  cv::Point2d* corner) {
  const double sigma = 0.5 * radius;
  cv::Point2d c = *corner - cv::Point2d(origin);
  const cv::Point2d start = c;
  for (int iter = 0; iter < 30; ++iter) {
    double A00 = 0, A01 = 0, A11 = 0, b0 = 0, b1 = 0;
    const int x0 = std::max(0, static_cast<int>(std::floor(c.x - radius)));
    const int x1 = std::min(gx.cols - 1, static_cast<int>(std::ceil(c.x + radius)));
    const int y0 = std::max(0, static_cast<int>(std::floor(c.y - radius)));
    const int y1 = std::min(gx.rows - 1, static_cast<int>(std::ceil(c.y + radius)));
    for (int y = y0; y <= y1; ++y) {
      const float* row_x = gx.ptr<float>(y);
      const float* row_y = gy.ptr<float>(y);
      const double dy = y - c.y;
      for (int x = x0; x <= x1; ++x) {
        const double dx = x - c.x;
        const double r2 = dx * dx + dy * dy;
        if (r2 > radius * radius) continue;
        const double w = std::exp(-0.5 * r2 / (sigma * sigma));
        const double g0 = row_x[x], g1 = row_y[x];
        const double a00 = w * g0 * g0, a01 = w * g0 * g1, a11 = w * g1 * g1;
        A00 += a00;
        A01 += a01;
        A11 += a11;
        b0 += a00 * x + a01 * y;
        b1 += a01 * x + a11 * y;
      }
    }
    const double det = A00 * A11 - A01 * A01;
    // Edges in one direction only (or none): nothing pins a corner down.
    if (!(det > 1e-6 * (A00 + A11) * (A00 + A11))) return false;
    const cv::Point2d next((A11 * b0 - A01 * b1) / det, (A00 * b1 - A01 * b0) / det);
    const double step = cv::norm(next - c);
    c = next;
    if (cv::norm(c - start) > 0.5 * radius) return false;
    if (step < 1e-4) break;
  }
  *corner = c + cv::Point2d(origin);
  return true;
}

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
  std::vector<cv::Point2f> board, seen(n);
  for (int b = 0; b < wb; ++b)
    for (int a = 0; a < wa; ++a) board.emplace_back(static_cast<float>(a), static_cast<float>(b));
  std::vector<cv::Point2f> board_others(n - 1), seen_others(n - 1), predicted;
  for (int b0 = 0; b0 + wb <= grid.rows; ++b0) {
    for (int a0 = 0; a0 + wa <= grid.cols; ++a0) {
      double side_sum = 0;
      int sides = 0;
      for (int b = 0; b < wb; ++b) {
        for (int a = 0; a < wa; ++a) {
          const cv::Point2d p = grid.At(a0 + a, b0 + b);
          seen[b * wa + a] = cv::Point2f(static_cast<float>(p.x), static_cast<float>(p.y));
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
        const cv::Mat H = cv::findHomography(board_others, seen_others, 0);
        if (H.empty()) return false;
        cv::perspectiveTransform(std::vector<cv::Point2f>{board[k]}, predicted, H);
        if (!(cv::norm(predicted[0] - seen[k]) <= tolerance)) return false;
      }
    }
  }
  return true;
}

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
  cv::Mat gx, gy;
  cv::Sobel(gray(box), gx, CV_32F, 1, 0, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
  cv::Sobel(gray(box), gy, CV_32F, 0, 1, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
  std::vector<cv::Point2f> refined(grid->px.size());
  for (int b = 0; b < grid->rows; ++b) {
    for (int a = 0; a < grid->cols; ++a) {
      const double radius = std::clamp(kWindowFraction * NearestLineDistance(*grid, a, b),
                                       kMinRadiusPx, kMaxRadiusPx);
      cv::Point2d corner = grid->At(a, b);
      if (!RefineCorner(gx, gy, box.tl(), radius, &corner)) return false;
      if (!LooksLikeXJunction(gray, corner, 0.5 * radius)) return false;
      refined[static_cast<size_t>(b) * grid->cols + a] =
          cv::Point2f(static_cast<float>(corner.x), static_cast<float>(corner.y));
    }
  }
  Grid refined_grid = *grid;
  refined_grid.px = std::move(refined);
  if (!FitsPerspective(refined_grid)) return false;
  *grid = std::move(refined_grid);
  return true;
}

/// Integer factors of the image pyramid searched, coarsest first. The sector
/// detector's cost grows with the pixels it looks at (about 25, 70 and 285 ms
/// of CPU for one 1920x1080 image at 1/4, 1/2 and full resolution), and it
/// finds squares from about 8 px up, so most boards of 30 px squares and more
/// are found at 1/4; the finer levels are for smaller squares and for boards
/// the coarser levels missed. (On METRIC's synthetic cell, 368 views of 30-40
/// px squares, 1/4 alone found 269 boards, 1/2 alone 322; a 1/3 level between
/// them saved no time overall.)
constexpr int kFactors[] = {4, 2, 1};
/// A level whose shorter side would be smaller than this is skipped: the
/// sector detector looks for corners in 17 px windows at its largest scale
/// and leaves out one to three of them at the image's borders, so such a
/// level holds too little image to be worth it.
constexpr int kMinLevelSide = 240;
/// Squares of margin kept around what may be a board's inner corners (a grid
/// found but rejected, a cluster of saddle points) when it is searched in a
/// crop: the outer squares, one more for a grid shifted by one line (see
/// FindGrid), and white around the board's outer corners for the detector.
constexpr double kCropMarginSquares = 2.5;
/// ... and at least this many pixels of the level searched, for the detector's
/// ignored border (see kMinLevelSide).
constexpr int kCropMarginMinPx = 40;

/// A cluster of saddle points is searched at a level only where its spacing
/// (the median distance between neighbouring points, at most a square's side)
/// is at least this many pixels of that level: the sector detector does not
/// find squares that small there, and most clusters in clutter are 5-15 px
/// apart at full resolution, so at 1/4 resolution their crops were ~750
/// fruitless searches on METRIC's synthetic cell (368 images). Such a cluster
/// is searched at the finer levels. 3 px saves 5-10 % of detection time there
/// and finds the same boards on every cell of bench_accuracy (20 seeds);
/// 4 px saved more but lost one view of 628 in the large cell.
constexpr double kMinSaddleSpacingPx = 3.0;

/// One level of the pyramid: the image scaled down by `factor` with every
/// pixel the mean of a factor x factor block, so that level pixel k has its
/// centre at factor * k + (factor - 1) / 2 in the full image (pixel centres
/// at integers, SPEC §2). The full image is cut to a multiple of the factor
/// first (at most factor - 1 pixels lost on the right and bottom), which keeps
/// that mapping exact.
struct Level {
  int factor = 1;
  cv::Mat image;
};

Level MakeLevel(const cv::Mat& gray, int factor) {
  Level level;
  level.factor = factor;
  if (factor == 1) {
    level.image = gray;
    return level;
  }
  const cv::Size size(gray.cols / factor, gray.rows / factor);
  cv::resize(gray(cv::Rect(0, 0, size.width * factor, size.height * factor)), level.image, size, 0,
             0, cv::INTER_AREA);
  return level;
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

/// A grid that was found but rejected: the full-image region around it, and
/// whether it is the board itself (most of its corners are X-junctions, not
/// clutter) rather than something else that the detector took for one.
struct Candidate {
  cv::Rect region;
  bool board = false;
};

/// A part of the full image that may hold a checkerboard's inner corners,
/// and the size of its squares there (px).
struct Region {
  cv::Rect box;
  double square = 0;
};

/// `region` grown by a margin for the outer squares and the sheet's white
/// border, and for the border that the sector detector ignores at a level of
/// `factor` (kCropMarginSquares, kCropMarginMinPx), cut to `image`.
cv::Rect WithMargin(const Region& region, int factor, const cv::Rect& image) {
  const int margin = static_cast<int>(std::ceil(std::max(
      kCropMarginSquares * region.square, static_cast<double>(kCropMarginMinPx * factor))));
  const cv::Rect& b = region.box;
  return cv::Rect(b.x - margin, b.y - margin, b.width + 2 * margin, b.height + 2 * margin) & image;
}

/// Regions of the full image that may hold a checkerboard: the clusters of
/// the saddle points of its half-resolution image, of size `half_size`.
std::vector<Region> BoardRegions(const std::vector<internal::SaddlePoint>& saddles,
                                 cv::Size half_size) {
  std::vector<Region> regions;
  for (const internal::SaddleRegion& cluster :
       internal::SaddleRegions(saddles, half_size, internal::SaddleRegionOptions{})) {
    // Half pixel k covers full pixels 2k and 2k + 1.
    regions.push_back({cv::Rect(2 * cluster.box.x, 2 * cluster.box.y, 2 * cluster.box.width + 2,
                                2 * cluster.box.height + 2),
                       2 * cluster.spacing});
  }
  return regions;
}

/// The full grid of inner corners, refined and verified, or nullopt.
///
/// OpenCV's sector-based detector (findChessboardCornersSB) is used because
/// the classic cv::findChessboardCorners took 4-15 s on cluttered 1920x1080
/// images with no board or a partly visible one, even with
/// CALIB_CB_FAST_CHECK. It is run coarse to fine (kFactors): the first level
/// where it finds a grid that passes verification at full resolution wins. The
/// corners are always refined on the full image by RefineGrid, from wherever
/// the level put them.
///
/// At each level it looks first where a board is likely, in crops, and only
/// then at the whole image: around the grids rejected so far (below), then
/// around the clusters of saddle points (BoardRegions, a few ms for the whole
/// image). A crop costs a few ms where the whole image costs 25, 70 or 285 ms
/// (1/4, 1/2, full resolution of 1920x1080), so the common case is a crop at
/// 1/4 plus the refinement on the board's bounding box. The whole image is
/// still searched at every level when the crops fail: the sector detector is
/// not monotonic in what it is shown, and it found boards in whole images (10
/// px squares, some oblique views) that it missed in crops around them. Only
/// the full-resolution one, a quarter of a second, is left out once a rejected
/// grid was the board itself: it can only find a second board, and a
/// calibration target is one.
///
/// Without CALIB_CB_ACCURACY, SB sometimes returns a grid shifted by one line
/// onto the ends of the outer black squares (seen on a board turned by about
/// 90°); verification rejects such a grid. CALIB_CB_ACCURACY (the detector on
/// a 2x upsampled image, several times slower) then searches again, only in a
/// crop around the rejected grid, and again at every finer level.
std::optional<Grid> FindGrid(const cv::Mat& gray, int cols, int rows) {
  const cv::Size pattern(cols, rows);
  // CALIB_CB_EXHAUSTIVE tries about 3x as many corners as seeds of a grid,
  // which finds boards among much clutter. The first whole image searched,
  // at the coarsest level, goes without it when a finer level follows: that
  // saved 5-10% of all detection time and found the same boards on METRIC's
  // synthetic cell, and a board it misses is searched for exhaustively at the
  // next level.
  const int quick = cv::CALIB_CB_NORMALIZE_IMAGE;
  const int thorough = quick | cv::CALIB_CB_EXHAUSTIVE;
  const int accurate = thorough | cv::CALIB_CB_ACCURACY;
  const cv::Rect whole_image(0, 0, gray.cols, gray.rows);
  Grid grid;
  grid.cols = cols;
  grid.rows = rows;
  std::vector<Candidate> candidates;

  // One search of `region` (full-image pixels) of one level: found (refined
  // and verified), nothing found, or a grid found but rejected, which is then
  // added to `candidates` unless one already covers it.
  enum class Outcome { kFound, kNone, kRejected };
  auto search = [&](const Level& level, cv::Rect region, int flags) {
    const int f = level.factor;
    // The region in level pixels: every level pixel whose block lies in it.
    const int x0 = (region.x + f - 1) / f, y0 = (region.y + f - 1) / f;
    const cv::Rect crop =
        cv::Rect(x0, y0, (region.x + region.width) / f - x0, (region.y + region.height) / f - y0) &
        cv::Rect(0, 0, level.image.cols, level.image.rows);
    if (crop.width < 3 * cols || crop.height < 3 * rows) return Outcome::kNone;
    std::vector<cv::Point2f> found;
    if (!cv::findChessboardCornersSB(level.image(crop), pattern, found, flags))
      return Outcome::kNone;
    if (found.size() != static_cast<size_t>(cols) * rows) return Outcome::kNone;
    // Crop pixel k is level pixel k + crop offset (an integer shift); level
    // pixel k has its centre at f k + (f - 1) / 2 in the full image.
    const float offset = 0.5f * static_cast<float>(f - 1);
    for (auto& p : found)
      p = static_cast<float>(f) * (p + cv::Point2f(crop.tl())) + cv::Point2f(offset, offset);
    // SB lists the corners row by row, cols per row (checked on boards and
    // images turned by every quarter turn); which way round, and so the
    // handedness, is left to Detect().
    grid.px = std::move(found);
    const Grid seen = grid;
    if (RefineGrid(gray, &grid)) return Outcome::kFound;

    const double square = MedianSquare(seen);
    const cv::Rect around = WithMargin({cv::boundingRect(seen.px), square}, f, whole_image);
    // The same board rejected again (at another level) is searched once.
    for (const Candidate& c : candidates)
      if (2 * (c.region & around).area() > std::min(c.region.area(), around.area()))
        return Outcome::kRejected;
    // The board itself, seen but not verified (as on boards seen very
    // obliquely), if three quarters of its corners are X-junctions even
    // before refinement.
    int junctions = 0;
    for (const auto& p : seen.px) junctions += LooksLikeXJunction(gray, p, 0.35 * square);
    candidates.push_back({around, 4 * junctions >= 3 * static_cast<int>(seen.px.size())});
    return Outcome::kRejected;
  };

  // The half-resolution image, made once: a level, and where saddle points
  // are looked for.
  cv::Mat half;
  auto level_of = [&](int f) {
    if (f != 2) return MakeLevel(gray, f);
    if (half.empty()) half = MakeLevel(gray, 2).image;
    return Level{2, half};
  };
  // The saddle points of the half-resolution image, where the image has more
  // than one level; and where they cluster.
  std::optional<std::vector<internal::SaddlePoint>> saddles;
  if (std::min(gray.cols, gray.rows) / 2 >= kMinLevelSide) {
    saddles = internal::FindSaddlePoints(level_of(2).image, internal::SaddleRegionOptions{});
    // The cascade's first stage: without a patch of grid among the saddle
    // points there is no board to search for (boards of fewer than 3 x 2
    // inner corners hold no such patch and are always searched).
    internal::GridPatchOptions patch;
    patch.rows = std::min(std::min(cols, rows), 3);
    if (std::max(cols, rows) >= 3 && patch.rows >= 2 && !internal::HasGridPatch(*saddles, patch))
      return std::nullopt;
  }
  std::optional<std::vector<Region>> saddle_regions;
  auto covered = [&](const cv::Rect& region, std::size_t num_candidates) {
    for (std::size_t k = 0; k < num_candidates; ++k) {
      const cv::Rect& c = candidates[k].region;
      if (2 * (c & region).area() > std::min(c.area(), region.area())) return true;
    }
    return false;
  };

  bool first = true;
  for (const int f : kFactors) {
    if (f > 1 && std::min(gray.cols, gray.rows) / f < kMinLevelSide) continue;
    const Level level = level_of(f);
    // The saddle points are looked for in the half-resolution image, before
    // the first level when another follows (an image too small for more than
    // one level is searched whole at once).
    if (!saddle_regions && (f > 1 || !first)) {
      if (!saddles)
        saddles = internal::FindSaddlePoints(level_of(2).image, internal::SaddleRegionOptions{});
      saddle_regions = BoardRegions(*saddles, level_of(2).image.size());
    }
    // Seen but rejected at a coarser level: look there first at this one, and
    // with the slower, more accurate corners. Grids rejected in a crop are
    // inside it, so they add no candidate.
    const std::size_t known = candidates.size();
    for (const int flags : {thorough, accurate}) {
      for (std::size_t k = 0; k < known; ++k) {
        if (search(level, candidates[k].region, flags) == Outcome::kFound) return grid;
        candidates.resize(known);
      }
    }
    // Then where the saddle points are; grids rejected there become
    // candidates.
    if (saddle_regions) {
      for (const Region& cluster : *saddle_regions) {
        if (cluster.square < kMinSaddleSpacingPx * f) continue;
        const cv::Rect region = WithMargin(cluster, f, whole_image);
        if (!covered(region, known) && search(level, region, thorough) == Outcome::kFound)
          return grid;
      }
    }
    // The whole image, except at full resolution once a rejected grid was the
    // board.
    const bool board_seen = std::any_of(candidates.begin(), candidates.end(),
                                        [](const Candidate& c) { return c.board; });
    if (f > 1 || !board_seen) {
      const int whole_flags = first && f > 1 ? quick : thorough;
      if (search(level, whole_image, whole_flags) == Outcome::kFound) return grid;
    }
    first = false;
    const std::size_t all = candidates.size();
    for (std::size_t k = known; k < all; ++k) {
      if (search(level, candidates[k].region, accurate) == Outcome::kFound) return grid;
      candidates.resize(all);
    }
  }
  return std::nullopt;
}

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

/// OpenCV's random state at the start of every detection.
constexpr std::uint64_t kRandomState = 0x5eed;

}  // namespace

CheckerboardDetector::CheckerboardDetector(std::shared_ptr<const CheckerboardTarget> target)
    : target_(std::move(target)) {
  if (!target_) throw std::invalid_argument("CheckerboardDetector: null target");
}

std::optional<Detection> CheckerboardDetector::Detect(const cv::Mat& gray) const {
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
  auto grid_or_none = FindGrid(gray, cols, rows);
  rng.state = callers_state;
  if (!grid_or_none) return std::nullopt;
  const Grid& grid = *grid_or_none;

  // Every re-indexing of the grid onto itself: target corner (i, j) is grid
  // point map(i, j). The quarter turns exist only for square grids.
  using Map = std::array<int, 6>;  // a = m0 + m1 i + m2 j, b = m3 + m4 i + m5 j
  std::vector<Map> maps = {{0, 1, 0, 0, 0, 1},
                           {cols - 1, -1, 0, rows - 1, 0, -1},
                           {cols - 1, -1, 0, 0, 0, 1},
                           {0, 1, 0, rows - 1, 0, -1}};
  if (cols == rows) {
    const int n = cols - 1;
    maps.push_back({0, 0, 1, 0, 1, 0});
    maps.push_back({n, 0, -1, 0, 1, 0});
    maps.push_back({0, 0, 1, n, -1, 0});
    maps.push_back({n, 0, -1, n, -1, 0});
  }
  auto grid_point = [&grid](const Map& m, int i, int j) {
    return grid.At(m[0] + m[1] * i + m[2] * j, m[3] + m[4] * i + m[5] * j);
  };

  const std::optional<int> black_parity = BlackParity(gray, grid);
  if (!black_parity) return std::nullopt;
  const Map* best = nullptr;
  double best_score = -1e9;
  for (const Map& m : maps) {
    // Handedness: the printed face seen from its -z side shows +x then +y
    // turning clockwise on screen (u right, v down), i.e. cross(d_i, d_j) > 0.
    cv::Point2d d_i(0, 0), d_j(0, 0);
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i + 1 < cols; ++i) d_i += grid_point(m, i + 1, j) - grid_point(m, i, j);
    for (int j = 0; j + 1 < rows; ++j)
      for (int i = 0; i < cols; ++i) d_j += grid_point(m, i, j + 1) - grid_point(m, i, j);
    if (d_i.x * d_j.y - d_i.y * d_j.x <= 0) continue;
    // SPEC §4: the square on the -x, -y side of corner (0, 0) is black. It
    // touches (0, 0) diagonally to target square (0, 0), between corners
    // (0, 0) and (1, 1), so both have one colour; square (0, 0) is an inner
    // cell, measured between four detected corners rather than extrapolated.
    const int a0 = m[0], b0 = m[3];
    const int a1 = m[0] + m[1] + m[2], b1 = m[3] + m[4] + m[5];
    const int parity = (std::min(a0, a1) + std::min(b0, b1)) % 2;
    if (parity != *black_parity) continue;
    // Boards that look the same turned (cols + rows even) leave several maps;
    // take the one whose i axis points most to the image's right, so views
    // of similar orientation number the board alike.
    const double score = d_i.x / (cv::norm(d_i) + 1e-12);
    if (score > best_score) {
      best_score = score;
      best = &m;
    }
  }
  if (!best) return std::nullopt;

  Detection detection;
  detection.ids.reserve(cols * rows);
  detection.points_px.reserve(cols * rows);
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < cols; ++i) {
      const cv::Point2d p = grid_point(*best, i, j);
      detection.ids.push_back(j * cols + i);
      detection.points_px.emplace_back(p.x, p.y);
    }
  }
  return detection;
}

}  // namespace handeye
