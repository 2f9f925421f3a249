// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// OpenCV drawing for the report's overlays: markers and arrows at sub-pixel
// positions, and text (cv::putText; Hershey fonts are ASCII only). The plots
// are SVG (report_svg.h).

#include <cmath>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace handeye::report {

/// Fixed-point factor of OpenCV's drawing `shift` argument (4 fractional bits).
constexpr int kShift = 4;
constexpr double kSubpixel = 1 << kShift;

/// A point at sub-pixel precision for drawing calls made with `kShift`. Pixel
/// (0, 0) is the centre of the top-left pixel (SPEC §2), as in OpenCV's drawing.
inline cv::Point Fixed(double x, double y) {
  return {static_cast<int>(std::lround(x * kSubpixel)),
          static_cast<int>(std::lround(y * kSubpixel))};
}
inline cv::Point Fixed(const cv::Point2d& p) { return Fixed(p.x, p.y); }

enum class Marker { kCircle, kDiamond, kCross };

/// Draws a marker of `size` pixels (full width) centred at `centre` (sub-pixel).
void DrawMarker(cv::Mat* image, const cv::Point2d& centre, Marker marker, double size,
                const cv::Scalar& color, int thickness = 1);
/// An arrow from `from` to `to` (pixels) with a head of `head` pixels.
void DrawArrow(cv::Mat* image, const cv::Point2d& from, const cv::Point2d& to,
               const cv::Scalar& color, int thickness, double head);

/// How text sits on its anchor: fractions of its width (0 left … 1 right) and
/// height (0 top … 1 bottom).
struct Align {
  double x = 0, y = 0;
};
/// Text (FONT_HERSHEY_SIMPLEX, anti-aliased) of `height` pixels (cap height).
void DrawText(cv::Mat* image, const std::string& text, const cv::Point2d& anchor, double height,
              const cv::Scalar& color, Align align = {}, int thickness = 1);
/// Width and height in pixels of DrawText's text.
cv::Size TextSize(const std::string& text, double height, int thickness = 1);

}  // namespace handeye::report
