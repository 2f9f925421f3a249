// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A small plotting library on cv::Mat for the report: axes with "nice" ticks,
// grid, labels (cv::putText; Hershey fonts are ASCII only, so units are
// spelled "deg", "px", "mm"), markers at sub-pixel positions, arrows,
// colour bars and legends. No Python, no display: the image is the output.

#include <Eigen/Core>
#include <functional>
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

enum class Marker { kCircle, kDisc, kSquare, kTriangle, kDiamond, kCross, kPlus };

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
/// Text turned 90° counter-clockwise (for y-axis labels), dark on a light background.
void DrawTextVertical(cv::Mat* image, const std::string& text, const cv::Point2d& centre,
                      double height, const cv::Scalar& color);

/// Ticks for [lo, hi]: multiples of a 1/2/5 × 10^k step, about `count` of them.
std::vector<double> NiceTicks(double lo, double hi, int count, double* step = nullptr);
/// A tick label with just the decimals the step needs ("0.25", "10", "-3").
std::string TickLabel(double value, double step);

/// One line of a legend: a marker or a line sample, and its text.
struct LegendEntry {
  std::string text;
  cv::Scalar color;
  Marker marker = Marker::kDisc;
  bool line = false;  ///< draw a line sample instead of the marker
};

/// A 2-D plot: a frame with ticks, grid and labels around a data area;
/// data-space drawing calls are clipped to the data area.
class Plot {
 public:
  /// `right_margin` leaves room for a colour bar or legend beside the data area.
  Plot(int width, int height, const std::string& title, int right_margin = 20);

  /// The title DrawFrame writes (the constructor's, unless changed before).
  void SetTitle(const std::string& title) { title_ = title; }
  void SetX(double lo, double hi, const std::string& label);
  /// `downward`: y grows downward (image rows), as in an image-plane plot.
  void SetY(double lo, double hi, const std::string& label, bool downward = false);
  /// Widens one range so a unit is as long in x as in y (maps, image planes).
  void EqualAspect();
  /// Draws background, grid, ticks, axis labels and title. Call after the
  /// ranges are set and before data.
  void DrawFrame(bool grid = true);

  /// Pixel position of a data point (in the whole image, sub-pixel).
  cv::Point2d Px(double x, double y) const;
  double PxPerUnitX() const { return area_.width / (x_hi_ - x_lo_); }

  // Data-space drawing, clipped to the data area.
  void Line(const std::vector<Eigen::Vector2d>& points, const cv::Scalar& color, int thickness = 1);
  void DashedLine(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const cv::Scalar& color);
  void Point(const Eigen::Vector2d& p, Marker marker, double size, const cv::Scalar& color,
             int thickness = 1);
  void Arrow(const Eigen::Vector2d& from, const Eigen::Vector2d& to, const cv::Scalar& color,
             int thickness = 1, double head = 8);
  /// A filled bar from y = 0 to `height` over [x0, x1].
  void Bar(double x0, double x1, double height, const cv::Scalar& fill);
  /// Text at a data point, offset by (dx, dy) pixels.
  void Label(const Eigen::Vector2d& p, const std::string& text, const cv::Scalar& color,
             double dx = 0, double dy = 0, Align align = {}, double height = 11);

  /// A vertical colour bar in the right margin, `lo` … `hi` with ticks.
  void ColorBar(double lo, double hi, const std::string& label,
                const std::function<cv::Scalar(double)>& color_of);
  /// Where a legend goes: inside the data area at its top right or top left,
  /// or in the right margin (which the constructor must have left wide enough).
  enum class Place { kInsideRight, kInsideLeft, kMargin };
  void Legend(const std::vector<LegendEntry>& entries, Place place = Place::kInsideRight);
  /// Width in pixels of Legend's box (to size a right margin for it).
  static int LegendWidth(const std::vector<LegendEntry>& entries);

  cv::Mat& image() { return image_; }
  const cv::Rect& area() const { return area_; }

 private:
  cv::Mat Area() { return image_(area_); }
  cv::Point2d AreaPx(double x, double y) const;

  cv::Mat image_;
  cv::Rect area_;
  std::string title_, x_label_, y_label_;
  double x_lo_ = 0, x_hi_ = 1, y_lo_ = 0, y_hi_ = 1;
  bool y_down_ = false;
};

}  // namespace handeye::report
