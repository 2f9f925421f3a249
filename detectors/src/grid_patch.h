// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Whether saddle points contain a piece of a checkerboard's corner grid: the
// cheap test that lets the checkerboard detector give up on an image without
// running OpenCV's search on it. Internal to the detectors library.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "saddle_regions.h"

namespace handeye::internal {

/// How HasGridPatch() looks.
struct GridPatchOptions {
  /// Corners of the patch across the first grid direction: 3 (a 3 x 3
  /// patch, which every board of at least 3 x 3 inner corners holds) or 2
  /// (3 x 2, for boards with two inner corners a side).
  int rows = 3;
  /// Nearest saddle points of each point tried as its neighbours on the grid.
  /// On a board these are its four neighbours along the grid lines and four
  /// diagonal ones; the rest is room for clutter next to the board.
  int neighbours = 10;
  /// Steps between neighbouring corners looked at (pixels of the image
  /// searched).
  double min_step_px = 1.5;
  double max_step_px = 300.0;
  /// A predicted corner is matched by a saddle point within this fraction of
  /// the shorter step of the patch plus `slack_px`: a plane seen in
  /// perspective changes its steps from one corner to the next. With 0.3
  /// every one of the 347 views found on METRIC's medium cell held a patch,
  /// as do the oblique, small and blurred views of grid_patch_test.cc.
  double tolerance = 0.3;
  /// Saddle points sit on integer pixels.
  double slack_px = 1.0;
  /// The two grid directions of a patch are at least this far from parallel
  /// (sine of the angle between them).
  double min_sine = 0.25;
  /// Neighbouring corners have Hessians at least this close to opposite, and
  /// diagonal ones to equal (cosine of the angle between them, HessianCosine
  /// in grid_patch.cc).
  double min_cosine = 0.5;
  /// Only saddle points whose Hessian eigenvalues are this close to equal and
  /// opposite (smaller / larger magnitude) are taken: X-junctions, not the
  /// staircase of an edge that a slightly turned square leaves in the pixels
  /// (0.02-0.06), which crowds the corners' neighbourhoods. Each of the 4164
  /// corners of the 347 views found on METRIC's medium cell was a saddle
  /// point of 0.59 or more.
  double min_eigen_ratio = 0.3;
};

/// A 3 x 3 (or 3 x 2) patch of corner grid found among saddle points.
struct GridPatch {
  /// Its corners (pixels of the image searched), row by row.
  std::vector<cv::Point> corners;
  /// Length of its longer step between neighbouring corners (px).
  double step_px = 0;
};

/// The patches of a checkerboard's inner corners among `saddles`, at most
/// one centred on each saddle point and at most `max_patches`: p - u, p,
/// p + u, the same three moved by v (and by -v for three rows), where p + u
/// and p + v are among p's nearest saddle points, the others lie where the
/// steps u and v predict, and the Hessians alternate in sign between
/// neighbours as the squares' colours do (SaddlePoint). Every board with
/// enough inner corners, found as saddle points, holds one; clutter seldom
/// does.
std::vector<GridPatch> FindGridPatches(const std::vector<SaddlePoint>& saddles,
                                       const GridPatchOptions& options,
                                       std::size_t max_patches = SIZE_MAX);

/// Corner grid grown among saddle points from a patch: a rectangle of grid
/// nodes, not all of them found.
struct Lattice {
  /// Nodes along the first direction of the patch it grew from, and along
  /// the second.
  int cols = 0, rows = 0;
  /// Row by row: node (a, b) at b * cols + a (pixels of the image searched),
  /// where found[b * cols + a] is set.
  std::vector<cv::Point> points;
  std::vector<char> found;
};

/// The lattices that `patches` grow into over `saddles`: from each corner,
/// the next one along a grid line is the X-junction nearest to where the
/// last step predicts it (within the patches' tolerance, FindGridPatches)
/// whose Hessian has the opposite sign, until no corner can grow. Lattices
/// of more than `max_points` corners are left out; each is grown once (a
/// patch whose centre is in a lattice grown before grows none). On a
/// checkerboard seen whole a lattice holds its inner corners, often with a
/// ring of the board's outer corners or of clutter around them; the caller
/// picks the board's rectangle and verifies it on the image.
std::vector<Lattice> GrowLattices(const std::vector<SaddlePoint>& saddles,
                                  const std::vector<GridPatch>& patches,
                                  const GridPatchOptions& options, std::size_t max_points);

/// True when `gray` (8-bit, single channel) may show a board of corners: the
/// saddle points of its half-resolution image (pixels averaged 2 x 2) hold a
/// 3 x `rows` patch, or the image is too small to tell (half-resolution
/// shorter side under kMinLevelSide). A few ms for 1920 x 1080.
bool MayShowCornerGrid(const cv::Mat& gray, int rows);

/// True when `saddles` hold a 3 x `options.rows` patch (FindGridPatches).
bool HasGridPatch(const std::vector<SaddlePoint>& saddles, const GridPatchOptions& options);

}  // namespace handeye::internal
