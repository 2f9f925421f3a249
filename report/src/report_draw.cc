// SPDX-License-Identifier: GPL-2.0-or-later
// The overlays' drawing primitives (report_draw.h).
#include "report_draw.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace handeye::report {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

// getTextSize reports a cap height of 22 px for FONT_HERSHEY_SIMPLEX at scale 1.
double FontScale(double height) { return height / 22.0; }

}  // namespace

void DrawMarker(cv::Mat* image, const cv::Point2d& c, Marker marker, double size,
                const cv::Scalar& color, int thickness) {
  const double r = size / 2;
  auto line = [&](double x0, double y0, double x1, double y1) {
    cv::line(*image, Fixed(c.x + x0, c.y + y0), Fixed(c.x + x1, c.y + y1), color, thickness,
             cv::LINE_AA, kShift);
  };
  switch (marker) {
    case Marker::kCircle:
      cv::circle(*image, Fixed(c), static_cast<int>(std::lround(r * kSubpixel)), color, thickness,
                 cv::LINE_AA, kShift);
      break;
    case Marker::kDiamond: {
      const std::vector<cv::Point> corners = {Fixed(c.x, c.y - r), Fixed(c.x + r, c.y),
                                              Fixed(c.x, c.y + r), Fixed(c.x - r, c.y)};
      cv::polylines(*image, std::vector<std::vector<cv::Point>>{corners}, true, color, thickness,
                    cv::LINE_AA, kShift);
      break;
    }
    case Marker::kCross:
      line(-r * 0.75, -r * 0.75, r * 0.75, r * 0.75);
      line(-r * 0.75, r * 0.75, r * 0.75, -r * 0.75);
      break;
  }
}

void DrawArrow(cv::Mat* image, const cv::Point2d& from, const cv::Point2d& to,
               const cv::Scalar& color, int thickness, double head) {
  cv::line(*image, Fixed(from), Fixed(to), color, thickness, cv::LINE_AA, kShift);
  const cv::Point2d d = to - from;
  const double len = std::hypot(d.x, d.y);
  if (len < 1e-9) return;
  const cv::Point2d u = d / len, n(-u.y, u.x);
  const double h = std::min(head, 0.5 * len + 2);
  const std::vector<cv::Point> tip = {Fixed(to), Fixed(to - h * u + 0.45 * h * n),
                                      Fixed(to - h * u - 0.45 * h * n)};
  cv::fillPoly(*image, std::vector<std::vector<cv::Point>>{tip}, color, cv::LINE_AA, kShift);
}

cv::Size TextSize(const std::string& text, double height, int thickness) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, FontScale(height), thickness, &baseline);
}

void DrawText(cv::Mat* image, const std::string& text, const cv::Point2d& anchor, double height,
              const cv::Scalar& color, Align align, int thickness) {
  const cv::Size size = TextSize(text, height, thickness);
  // putText's origin is the bottom-left of the capitals (the baseline).
  const cv::Point origin(static_cast<int>(std::lround(anchor.x - align.x * size.width)),
                         static_cast<int>(std::lround(anchor.y + (1.0 - align.y) * size.height)));
  cv::putText(*image, text, origin, kFont, FontScale(height), color, thickness, cv::LINE_AA);
}

}  // namespace handeye::report
