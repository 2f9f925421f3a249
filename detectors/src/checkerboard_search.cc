// SPDX-License-Identifier: GPL-2.0-or-later
#include "checkerboard_search.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "grid_patch.h"
#include "saddle_regions.h"

namespace handeye::internal {
namespace {

/// Integer factors of the image pyramid searched, coarsest first. The sector
/// detector's cost grows with the pixels it looks at (about 25, 70 and 285 ms
/// of CPU for one 1920x1080 image at 1/4, 1/2 and full resolution), and it
/// finds squares from about 8 px up, so most boards of 30 px squares and more
/// are found at 1/4; the finer levels are for smaller squares and for boards
/// the coarser levels missed. (On METRIC's synthetic cell, 368 views of 30-40
/// px squares, 1/4 alone found 269 boards, 1/2 alone 322; a 1/3 level between
/// them saved no time overall.)
constexpr int kFactors[] = {4, 2, 1};
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

/// A crop of at least this share of the image's area is the whole image.
constexpr double kWholeImageShare = 0.95;

/// One level of the pyramid: the image scaled down by `factor` (BlockMean).
struct Level {
  int factor = 1;
  cv::Mat image;
};

/// A grid that was found but rejected: the full-image region around it.
struct Candidate {
  cv::Rect region;
  /// Not a grid shifted by one line, which the accurate search
  /// (CALIB_CB_ACCURACY) mends, but a board too oblique or too blurred to
  /// refine, which no finer level's search changes (RefineGrid always refines
  /// on the full image); not searched again. So where the grid less any one
  /// of its outer lines does not verify either (OneLineOff), where the
  /// lattice of saddle points held it and it did not verify, or where the
  /// accurate search found a grid here too that did not.
  bool settled = false;
};

/// A part of the full image that may hold a checkerboard's inner corners,
/// and the size of its squares there (px).
struct Region {
  cv::Rect box;
  double square = 0;
  /// Squares of margin beyond kCropMarginSquares (see WithMargin).
  double extra_squares = 0;
  /// Already searched (patch regions are searched at one level).
  bool searched = false;
};

/// Whether two regions share more than half of the smaller one.
bool Overlap(const cv::Rect& a, const cv::Rect& b) {
  return 2 * (a & b).area() > std::min(a.area(), b.area());
}

/// `region` grown by a margin for the outer squares and the sheet's white
/// border, and for the border that the sector detector ignores at a level of
/// `factor` (kCropMarginSquares, kCropMarginMinPx), cut to `image`.
cv::Rect WithMargin(const Region& region, int factor, const cv::Rect& image) {
  const int margin = static_cast<int>(
      std::ceil(std::max((kCropMarginSquares + region.extra_squares) * region.square,
                         static_cast<double>(kCropMarginMinPx * factor))));
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

/// Regions of the full image around the patches of corner grid found in its
/// half-resolution image (FindGridPatches): patches that share a corner are
/// one region, the bounding box of their corners, with squares of the
/// patches' median step. Regions with the most corners first. A board of
/// `longest_side` inner corners a side may reach that many less three squares
/// beyond a 3 x 3 patch when only one patch of it was found: the margin
/// grows by as much.
std::vector<Region> PatchRegions(const std::vector<GridPatch>& patches, int longest_side) {
  const double extra_squares = std::max(0, longest_side - 3);
  std::vector<int> parent(patches.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&parent](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::map<std::pair<int, int>, int> owner;
  for (int i = 0; i < static_cast<int>(patches.size()); ++i) {
    for (const cv::Point& c : patches[i].corners) {
      const auto [it, fresh] = owner.emplace(std::make_pair(c.x, c.y), i);
      if (!fresh) parent[root(i)] = root(it->second);
    }
  }
  struct Members {
    std::vector<cv::Point> corners;
    std::vector<double> steps;
  };
  std::map<int, Members> groups;
  for (const auto& [xy, i] : owner) groups[root(i)].corners.emplace_back(xy.first, xy.second);
  for (int i = 0; i < static_cast<int>(patches.size()); ++i)
    groups[root(i)].steps.push_back(patches[i].step_px);
  std::vector<std::pair<std::size_t, Region>> sized;
  for (auto& [id, members] : groups) {
    std::vector<double>& steps = members.steps;
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    const cv::Rect box = cv::boundingRect(members.corners);
    // Half pixel k covers full pixels 2k and 2k + 1.
    sized.push_back({members.corners.size(),
                     {cv::Rect(2 * box.x, 2 * box.y, 2 * box.width + 2, 2 * box.height + 2),
                      2 * steps[steps.size() / 2], extra_squares}});
  }
  std::stable_sort(sized.begin(), sized.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Region> regions;
  for (const auto& entry : sized) regions.push_back(entry.second);
  return regions;
}

/// Patch regions searched (the first, with the most corners): each costs a
/// search, and clutter may hold a few patches of its own.
constexpr std::size_t kMaxPatchSearches = 8;

/// The grid of `cols` x `rows` corners (either way round) within `lattice`
/// (corners of the half-resolution image) that refines and verifies on the
/// full image (RefineGrid); nullopt when there is none, or more than one
/// (a larger pattern than the target's). The bounding box of each window of
/// the lattice that holds such a grid whole but does not verify is added to
/// `*refused`.
std::optional<Grid> GridInLattice(const cv::Mat& gray, const Lattice& lattice, int cols, int rows,
                                  std::vector<cv::Rect>* refused) {
  std::optional<Grid> only;
  for (const bool across : {false, true}) {
    if (across && cols == rows) break;
    // The window's size in lattice nodes.
    const int width = across ? rows : cols, height = across ? cols : rows;
    for (int b0 = 0; b0 + height <= lattice.rows; ++b0) {
      for (int a0 = 0; a0 + width <= lattice.cols; ++a0) {
        Grid grid;
        grid.cols = cols;
        grid.rows = rows;
        grid.px.resize(static_cast<std::size_t>(cols) * rows);
        bool missing = false;
        for (int b = 0; b < height; ++b) {
          for (int a = 0; a < width; ++a) {
            const std::size_t node = static_cast<std::size_t>(b0 + b) * lattice.cols + (a0 + a);
            missing |= lattice.found[node] == 0;
            // Half pixel k has its centre at 2k + 0.5 in the full image.
            const cv::Point& p = lattice.points[node];
            const std::size_t k = across ? static_cast<std::size_t>(a) * cols + b
                                         : static_cast<std::size_t>(b) * cols + a;
            grid.px[k] = cv::Point2f(2.0f * p.x + 0.5f, 2.0f * p.y + 0.5f);
          }
        }
        if (missing) continue;
        const cv::Rect box = cv::boundingRect(grid.px);
        if (!RefineGrid(gray, &grid)) {
          refused->push_back(box);
          continue;
        }
        if (only) return std::nullopt;
        only = std::move(grid);
      }
    }
  }
  return only;
}

}  // namespace

/// The full grid of inner corners, refined and verified, or nullopt.
///
/// First without OpenCV: the saddle points of the half-resolution image, the
/// 3 x 3 patches of corner grid among them (none: no board, the image is
/// done in a few ms), and the lattices those patches grow into; a window of
/// the board's size in a lattice that refines and verifies is the board. Most
/// boards seen whole are found so. The rest is OpenCV's sector detector:
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
/// searched only where the saddle points cannot say where a board is (an
/// image too small for them, a board too small for a patch of grid); before
/// the patches of grid and their lattices, it found boards (10 px squares,
/// some oblique views) that crops missed, but since then none (see below). The
/// full-resolution whole image, a quarter of a second, is searched only where
/// it is the first level (an image too small for coarser ones).
///
/// Without CALIB_CB_ACCURACY, SB sometimes returns a grid shifted by one line
/// onto the ends of the outer black squares (seen on a board turned by about
/// 90°); verification rejects such a grid. CALIB_CB_ACCURACY (the detector on
/// a 2x upsampled image, several times slower) then searches again, only in a
/// crop around the rejected grid, and again at every finer level; but only
/// where the grid less one of its outer lines verifies (OneLineOff). The one
/// accurate search METRIC still made (a grid in clutter, 45-55 ms of wall)
/// found nothing, as the three made on all our captures before had not.
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
  // The grids of corners the lattices held whole that did not verify.
  std::vector<cv::Rect> refused;

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

    const cv::Rect box = cv::boundingRect(seen.px);
    const cv::Rect around = WithMargin({box, MedianSquare(seen)}, f, whole_image);
    // The same board rejected again (at another level) is searched once.
    for (const Candidate& c : candidates)
      if (Overlap(c.region, around)) return Outcome::kRejected;
    // Where a lattice held it and it did not refine, or where it is no
    // board's grid shifted by one line, it is settled at once.
    const bool held = std::any_of(refused.begin(), refused.end(),
                                  [&](const cv::Rect& r) { return Overlap(r, box); });
    const bool settled = held || !OneLineOff(gray, seen);
    candidates.push_back({around, settled});
    return Outcome::kRejected;
  };

  // The half-resolution image, made once: a level, and where saddle points
  // are looked for.
  cv::Mat half;
  auto level_of = [&](int f) {
    if (f != 2) return Level{f, BlockMean(gray, f)};
    if (half.empty()) half = BlockMean(gray, 2);
    return Level{2, half};
  };
  // The saddle points of the half-resolution image, where the image has more
  // than one level; and where they cluster.
  std::optional<std::vector<internal::SaddlePoint>> saddles;
  std::optional<std::vector<Region>> saddle_regions;
  std::vector<Region> patch_regions;
  // The patches of grid said where a board may be (see the whole-image
  // search below).
  bool located = false;
  if (std::min(gray.cols, gray.rows) / 2 >= kMinLevelSide) {
    saddles = internal::FindSaddlePoints(level_of(2).image, internal::SaddleRegionOptions{});
    // The cascade's first stage: without a patch of grid among the saddle
    // points there is no board to search for (boards of fewer than 3 x 2
    // inner corners hold no such patch and are always searched).
    internal::GridPatchOptions patch;
    patch.rows = std::min(std::min(cols, rows), 3);
    if (std::max(cols, rows) >= 3 && patch.rows >= 2) {
      const std::vector<GridPatch> patches = FindGridPatches(*saddles, patch);
      if (patches.empty()) return std::nullopt;
      // Most boards seen whole are the lattice the patches grow into: refined
      // and verified, they are found without any of OpenCV's searches (the
      // crops and levels below are for the rest).
      for (const Lattice& lattice :
           GrowLattices(*saddles, patches, patch, 4 * static_cast<std::size_t>(cols) * rows))
        if (std::optional<Grid> found = GridInLattice(gray, lattice, cols, rows, &refused))
          return found;
      patch_regions = PatchRegions(patches, std::max(cols, rows));
      located = true;
    }
  }
  auto covered = [&](const cv::Rect& region, std::size_t num_candidates) {
    for (std::size_t k = 0; k < num_candidates; ++k) {
      const cv::Rect& c = candidates[k].region;
      if (Overlap(c, region)) return true;
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
      if (located) {
        // Where patches of grid say where a board may be, a cluster beyond
        // the reach of every patch, searched or not (the patch and as many
        // squares as the board may extend past it), is clutter: leaving those
        // out changed no view of METRIC, the METRIC-like capture, six
        // rendered cells, ViSP's eye-in-hand set or the checkerboard by view
        // angle (seeds 1, 3, 5), and saved 14 crops (30-40 ms of wall) on the
        // METRIC-like image that cost most.
        std::vector<cv::Rect> reach;
        for (const Region& patch : patch_regions)
          reach.push_back(WithMargin(patch, 1, whole_image));
        auto beyond = [&reach](const Region& cluster) {
          for (const cv::Rect& r : reach)
            if ((r & cluster.box).area() > 0) return false;
          return true;
        };
        saddle_regions->erase(
            std::remove_if(saddle_regions->begin(), saddle_regions->end(), beyond),
            saddle_regions->end());
      }
    }
    // Seen but rejected at a coarser level: look there first at this one, and
    // with the slower, more accurate corners. Grids rejected in a crop are
    // inside it, so they add no candidate.
    const std::size_t known = candidates.size();
    // Searches candidate k with `flags`; true when it found the board.
    auto search_candidate = [&](std::size_t k, int flags) {
      if (candidates[k].settled) return false;
      const std::size_t before = candidates.size();
      const Outcome outcome = search(level, candidates[k].region, flags);
      if (outcome == Outcome::kFound) return true;
      candidates.resize(before);
      if (flags == accurate && outcome == Outcome::kRejected) candidates[k].settled = true;
      return false;
    };
    for (const int flags : {thorough, accurate})
      for (std::size_t k = 0; k < known; ++k)
        if (search_candidate(k, flags)) return grid;
    // Where the patches of corner grid are (the cascade's first stage found
    // them), each once, at the coarsest level where its squares are not too
    // small: at 1/4 a crop costs a few ms where the whole image costs 25.
    // These searches come on top of the ones below, which ran alone before;
    // one that finds nothing leaves no trace (OpenCV's random state and the
    // candidates are put back), so that the searches below find the boards
    // they found without them. Searching the patches at finer levels as well
    // found no more boards on METRIC and cost 5 % more.
    for (std::size_t k = 0; k < std::min(patch_regions.size(), kMaxPatchSearches); ++k) {
      Region& patch = patch_regions[k];
      if (patch.searched || patch.square < kMinSaddleSpacingPx * f) continue;
      patch.searched = true;
      const std::uint64_t rng_state = cv::theRNG().state;
      const std::size_t before = candidates.size();
      if (search(level, WithMargin(patch, f, whole_image), thorough) == Outcome::kFound)
        return grid;
      cv::theRNG().state = rng_state;
      candidates.resize(before);
    }
    // Then where the saddle points are; grids rejected there become
    // candidates. A cluster spread over the whole image (clutter everywhere)
    // makes its crop the image itself, searched thoroughly: the whole-image
    // search below would repeat it.
    bool whole_searched = false;
    if (saddle_regions) {
      for (const Region& cluster : *saddle_regions) {
        if (cluster.square < kMinSaddleSpacingPx * f) continue;
        const cv::Rect region = WithMargin(cluster, f, whole_image);
        if (covered(region, known)) continue;
        if (search(level, region, thorough) == Outcome::kFound) return grid;
        whole_searched |= region.area() >= kWholeImageShare * whole_image.area();
      }
    }
    // The whole image, only where nothing says where a board may be (an image
    // too small for the saddle points, a board too small for a patch of
    // grid), and not at full resolution once a coarser level was searched
    // whole. Where patches of grid were found, the whole image at 1/4 and 1/2
    // after the crops found no board in 115 searches: METRIC (1004 images,
    // none searched whole), the METRIC-like capture (1004), the rendered
    // small, medium, large and noisy cells, ViSP's and industrial_calibration's
    // sets, the checkerboard by view angle (seeds 1, 3, 5; 600 views, all
    // found as before). They cost 90-100 ms of wall per image where they ran
    // (clutter, or a board too oblique to verify).
    if (!located && (f > 1 || first) && !whole_searched) {
      const int whole_flags = first && f > 1 ? quick : thorough;
      if (search(level, whole_image, whole_flags) == Outcome::kFound) return grid;
    }
    first = false;
    for (std::size_t k = known, all = candidates.size(); k < all; ++k)
      if (search_candidate(k, accurate)) return grid;
  }
  return std::nullopt;
}

}  // namespace handeye::internal
