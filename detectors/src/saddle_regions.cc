// SPDX-License-Identifier: GPL-2.0-or-later
#include "saddle_regions.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace handeye::internal {
namespace {

struct Hessian {
  float xx, xy, yy;
};

/// The second derivatives at pixel x of `row` by the 3x3 Sobel kernels
/// (cv::Sobel's of orders 2/0, 1/1, 0/2): [1 -2 1] along a direction times
/// [1 2 1] across it, and [-1 0 1] along both.
inline Hessian SobelHessian(const float* above, const float* row, const float* below, int x) {
  const auto along = [x](const float* r) { return r[x - 1] - 2.0f * r[x] + r[x + 1]; };
  const auto across = [x](const float* r) { return r[x - 1] + 2.0f * r[x] + r[x + 1]; };
  return {along(above) + 2.0f * along(row) + along(below),
          (below[x + 1] - below[x - 1]) - (above[x + 1] - above[x - 1]),
          across(above) - 2.0f * across(row) + across(below)};
}

}  // namespace

cv::Mat BlockMean(const cv::Mat& gray, int factor) {
  if (factor == 1) return gray;
  const cv::Size size(gray.cols / factor, gray.rows / factor);
  cv::Mat scaled;
  cv::resize(gray(cv::Rect(0, 0, size.width * factor, size.height * factor)), scaled, size, 0, 0,
             cv::INTER_AREA);
  return scaled;
}

std::vector<SaddlePoint> FindSaddlePoints(const cv::Mat& gray, const SaddleRegionOptions& options) {
  CV_Assert(gray.type() == CV_8UC1);
  std::vector<SaddlePoint> saddles;
  const int border = 2;  // the smoothing and derivatives there see replicated pixels
  if (gray.cols <= 2 * border || gray.rows <= 2 * border) return saddles;

  cv::Mat smooth;
  gray.convertTo(smooth, CV_32F);
  cv::GaussianBlur(smooth, smooth, cv::Size(), options.sigma_px, options.sigma_px,
                   cv::BORDER_REPLICATE);
  // Saddle strength -det(H) = Ixy^2 - Ixx Iyy. At the centre of an ideal
  // X-junction of contrast C (squares at -C/2 and +C/2) smoothed by a Gaussian
  // of sigma, Ixx = Iyy = 0 and Ixy = C / (pi sigma^2); the 3x3 Sobel kernels
  // estimate each second derivative 4x over.
  const double ixy = 4.0 * options.min_contrast / (M_PI * options.sigma_px * options.sigma_px);
  const auto threshold = static_cast<float>(ixy * ixy);
  // The derivatives and the strength in one pass, and the local maxima in
  // another: every image is searched, with a board or not, and three Sobel
  // images, their products and a dilation to find the maxima took two thirds
  // of the search on METRIC. Strength inside a one-pixel frame, which the
  // maxima (two pixels in) need.
  cv::Mat strength(smooth.size(), CV_32F, cv::Scalar(0));
  for (int y = 1; y + 1 < smooth.rows; ++y) {
    const float *above = smooth.ptr<float>(y - 1), *row = smooth.ptr<float>(y),
                *below = smooth.ptr<float>(y + 1);
    float* out = strength.ptr<float>(y);
    for (int x = 1; x + 1 < smooth.cols; ++x) {
      const Hessian h = SobelHessian(above, row, below, x);
      out[x] = h.xy * h.xy - h.xx * h.yy;
    }
  }
  // Local maxima (no greater neighbour of the eight) above the threshold.
  // Few pixels pass the threshold: with SSE2 it is tested four at a time
  // (pixel by pixel, the test and its branch were 40 % of the search).
  for (int y = border; y < strength.rows - border; ++y) {
    const float *above = strength.ptr<float>(y - 1), *row = strength.ptr<float>(y),
                *below = strength.ptr<float>(y + 1);
    const auto keep_if_maximum = [&](int x) {
      const float s = row[x];
      if (s >= above[x - 1] && s >= above[x] && s >= above[x + 1] && s >= row[x - 1] &&
          s >= row[x + 1] && s >= below[x - 1] && s >= below[x] && s >= below[x + 1]) {
        const Hessian h = SobelHessian(smooth.ptr<float>(y - 1), smooth.ptr<float>(y),
                                       smooth.ptr<float>(y + 1), x);
        saddles.push_back({{x, y}, h.xx, h.xy, h.yy});
      }
    };
    const int end = strength.cols - border;
    int x = border;
#if defined(__SSE2__)
    const __m128 limit = _mm_set1_ps(threshold);
    for (; x + 4 <= end; x += 4) {
      for (int above_limit = _mm_movemask_ps(_mm_cmpgt_ps(_mm_loadu_ps(row + x), limit));
           above_limit != 0; above_limit &= above_limit - 1)
        keep_if_maximum(x + __builtin_ctz(static_cast<unsigned>(above_limit)));
    }
#endif
    for (; x < end; ++x)
      if (row[x] > threshold) keep_if_maximum(x);
  }
  return saddles;
}

std::vector<SaddleRegion> SaddleRegions(const cv::Mat& gray, const SaddleRegionOptions& options) {
  return SaddleRegions(FindSaddlePoints(gray, options), gray.size(), options);
}

std::vector<SaddleRegion> SaddleRegions(const std::vector<SaddlePoint>& saddles, cv::Size size,
                                        const SaddleRegionOptions& options) {
  std::vector<SaddleRegion> regions;
  if (static_cast<int>(saddles.size()) < options.min_points) return regions;
  std::vector<cv::Point> points;
  points.reserve(saddles.size());
  for (const SaddlePoint& s : saddles) points.push_back(s.pixel);

  // Single-linkage clusters: points in cells of the link distance, each
  // compared with those of its own and the 8 neighbouring cells.
  const double link2 = options.link_px * options.link_px;
  const int cell = std::max(1, static_cast<int>(std::ceil(options.link_px)));
  const int cells_x = size.width / cell + 1, cells_y = size.height / cell + 1;
  std::vector<std::vector<int>> cells(static_cast<std::size_t>(cells_x) * cells_y);
  for (int i = 0; i < static_cast<int>(points.size()); ++i)
    cells[static_cast<std::size_t>(points[i].y / cell) * cells_x + points[i].x / cell].push_back(i);
  std::vector<int> parent(points.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&parent](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  // Distance from each point to its nearest neighbour within the link.
  std::vector<double> nearest2(points.size(), link2);
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const int cx = points[i].x / cell, cy = points[i].y / cell;
    for (int y = std::max(0, cy - 1); y <= std::min(cells_y - 1, cy + 1); ++y) {
      for (int x = std::max(0, cx - 1); x <= std::min(cells_x - 1, cx + 1); ++x) {
        for (const int j : cells[static_cast<std::size_t>(y) * cells_x + x]) {
          if (j == i) continue;
          const double dx = points[i].x - points[j].x, dy = points[i].y - points[j].y;
          const double d2 = dx * dx + dy * dy;
          if (d2 > link2) continue;
          nearest2[i] = std::min(nearest2[i], d2);
          parent[root(i)] = root(j);
        }
      }
    }
  }

  std::vector<std::vector<int>> members(points.size());
  for (int i = 0; i < static_cast<int>(points.size()); ++i) members[root(i)].push_back(i);
  for (const auto& cluster : members) {
    if (static_cast<int>(cluster.size()) < options.min_points) continue;
    std::vector<cv::Point> cluster_points;
    std::vector<double> spacing;
    for (const int i : cluster) {
      cluster_points.push_back(points[i]);
      spacing.push_back(std::sqrt(nearest2[i]));
    }
    std::nth_element(spacing.begin(), spacing.begin() + spacing.size() / 2, spacing.end());
    regions.push_back({cv::boundingRect(cluster_points), spacing[spacing.size() / 2],
                       static_cast<int>(cluster.size())});
  }
  std::sort(regions.begin(), regions.end(),
            [](const SaddleRegion& a, const SaddleRegion& b) { return a.points > b.points; });
  if (static_cast<int>(regions.size()) > options.max_regions) regions.resize(options.max_regions);
  return regions;
}

}  // namespace handeye::internal
