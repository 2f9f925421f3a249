// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The checkerboard detector's grid of inner corners: sub-pixel refinement on
// the full image and the checks that it is a board seen in perspective.
// Internal to the detectors library.

#include <opencv2/core.hpp>
#include <vector>

namespace handeye::internal {

/// Grid of detected corners as OpenCV orders them: point (a, b) at
/// b * cols + a, a in [0, cols), b in [0, rows).
struct Grid {
  int cols = 0, rows = 0;
  std::vector<cv::Point2f> px;
  cv::Point2d At(int a, int b) const { return px[static_cast<size_t>(b) * cols + a]; }
};

/// True when the image around `c` looks like a checkerboard X-junction on a
/// ring of `radius` px (see the definition).
bool LooksLikeXJunction(const cv::Mat& gray, const cv::Point2d& c, double radius);

/// Refines every corner of the grid in place; false if one fails or does
/// not look like a checkerboard corner, or if together they are not where
/// a plane seen in perspective would put them.
bool RefineGrid(const cv::Mat& gray, Grid* grid);

/// True when `grid` less one of its four outer lines refines and verifies
/// (RefineGrid): the rest of its corners are a board's, so the grid may be
/// that board's shifted by one line. Grids of fewer than 3 lines a side have
/// too few corners left to judge by and always count.
bool OneLineOff(const cv::Mat& gray, const Grid& grid);

/// Median distance (px) between grid neighbours: the size of a square.
double MedianSquare(const Grid& grid);

}  // namespace handeye::internal
