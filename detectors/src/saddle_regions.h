// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Where in an image a checkerboard may be: clusters of saddle points, found
// in a few milliseconds, so that the checkerboard detector can search crops
// instead of whole images at fine resolution. Internal to the detectors
// library.

#include <opencv2/core/mat.hpp>
#include <vector>

namespace handeye::internal {

/// `gray` scaled down by `factor` with every pixel the mean of a factor x
/// factor block, so that pixel k of the result has its centre at
/// factor * k + (factor - 1) / 2 in `gray` (pixel centres at integers, SPEC
/// §2). `gray` is cut to a multiple of the factor first (at most factor - 1
/// pixels lost on the right and bottom), which keeps that mapping exact.
/// Saddle points are looked for at factor 2.
cv::Mat BlockMean(const cv::Mat& gray, int factor);

/// A scaled image whose shorter side would be smaller than this is not
/// searched: OpenCV's sector detector looks for corners in 17 px windows at
/// its largest scale and leaves out one to three of them at the image's
/// borders, so such an image holds too little to be worth it; and an image
/// whose half-resolution image is smaller gets no first stage.
constexpr int kMinLevelSide = 240;

/// How SaddleRegions() looks for clusters of X-junctions.
struct SaddleRegionOptions {
  /// Gaussian smoothing before the second derivatives, in pixels of the
  /// image searched: 1 px suits squares of 4 px and more there.
  double sigma_px = 1.0;
  /// Weakest X-junction kept: the grey-level difference between its dark and
  /// light squares. Boards printed black on white and seen through a lens
  /// have 100-200; shadows and glare rarely take them below 40.
  double min_contrast = 20.0;
  /// Saddle points no farther apart than this (pixels of the image searched)
  /// join one cluster: neighbouring corners of squares up to this size.
  double link_px = 24.0;
  /// Fewest saddle points in a cluster worth searching.
  int min_points = 6;
  /// Most clusters returned (those with the most points).
  int max_regions = 8;
};

/// One saddle point: where it is (pixels of the image searched) and the
/// smoothed grey level's second derivatives there (3x3 Sobel of the smoothed
/// image). Neighbouring inner corners of a checkerboard have Hessians of
/// opposite sign (the dark squares swap sides), so the Frobenius product of
/// theirs is negative.
struct SaddlePoint {
  cv::Point pixel;
  float dxx = 0, dxy = 0, dyy = 0;
};

/// The saddle points of `gray` (8-bit, single channel), smoothed: local
/// maxima of -det(H) above the strength of an X-junction of
/// `options.min_contrast`, away from the border.
std::vector<SaddlePoint> FindSaddlePoints(const cv::Mat& gray, const SaddleRegionOptions& options);

/// One cluster of saddle points (pixels of the image searched).
struct SaddleRegion {
  cv::Rect box;    ///< bounding box of the points
  double spacing;  ///< median distance from a point to its nearest neighbour
  int points;      ///< number of points
};

/// The clusters of saddle points of `gray` (8-bit, single channel),
/// smoothed: points where the grey level's Hessian has a strongly negative
/// determinant, as at the X-junction where four squares of a checkerboard meet
/// (straight edges give none, and an L corner little). Largest clusters first.
std::vector<SaddleRegion> SaddleRegions(const cv::Mat& gray, const SaddleRegionOptions& options);
/// The same from points FindSaddlePoints() found in an image of `size`.
std::vector<SaddleRegion> SaddleRegions(const std::vector<SaddlePoint>& saddles, cv::Size size,
                                        const SaddleRegionOptions& options);

}  // namespace handeye::internal
