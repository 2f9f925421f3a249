// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The report's plots as SVG written inline into index.html: vector, any
// UTF-8 text (°, ×, −), axes with ticks and labels. Text is escaped, numbers
// are written the same in every locale, and a shape with a coordinate that
// is not finite is left out (a NaN in the data leaves a gap, never broken
// markup).

#include <Eigen/Core>
#include <functional>
#include <opencv2/core/types.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace handeye::report {

/// An SVG colour ("#rrggbb") of an OpenCV BGR colour.
std::string Hex(const cv::Scalar& bgr);

enum class Shape { kRing, kDisc, kSquare, kTriangle, kDiamond, kCross };

/// One SVG element after another, in drawing coordinates (CSS pixels, y down).
class Svg {
 public:
  using P = Eigen::Vector2d;
  /// `title` is the plot's accessible name (escaped here).
  Svg(double width, double height, const std::string& title);

  /// A polyline, broken where a point is not finite. `style`: extra
  /// attributes, e.g. stroke-dasharray="4 3".
  void Line(const std::vector<P>& points, const std::string& colour, double width = 1,
            const std::string& style = "");
  void Polygon(const std::vector<P>& points, const std::string& fill);
  void Rect(const P& corner, const P& opposite, const std::string& fill,
            const std::string& stroke = "none");
  void Mark(const P& at, Shape shape, double size, const std::string& colour, double width = 1.5);
  void Arrow(const P& from, const P& to, const std::string& colour, double width, double head);
  /// `anchor`: start, middle or end; `turned`: rotated 90° counter-clockwise about `at`.
  void Text(const P& at, const std::string& text, double size, const std::string& colour,
            const char* anchor = "start", bool turned = false);
  /// Later shapes are clipped to the rectangle until EndClip().
  void BeginClip(const P& corner, const P& size);
  void EndClip() { out_ << "</svg>\n"; }

  /// The finished element.
  std::string str() const { return out_.str() + "</svg>\n"; }

 private:
  std::ostringstream out_;
};

/// Ticks for [lo, hi]: multiples of a 1/2/2.5/5 × 10^k step, about `count` of them.
std::vector<double> NiceTicks(double lo, double hi, int count, double* step = nullptr);
/// Approximate width (px) of `text` at font `size` (px): for legends' boxes.
double TextWidth(const std::string& text, double size);

/// A 2-D plot: a frame with grid, ticks, axis labels and a title around a
/// data area, on an Svg; At() maps data to drawing coordinates.
class SvgPlot {
 public:
  /// `right_margin` leaves room for a colour bar or a legend.
  SvgPlot(double width, double height, const std::string& title, double right_margin = 20);

  /// The title Frame() writes (the constructor's, unless changed before).
  void SetTitle(const std::string& title) { title_ = title; }
  void SetX(double lo, double hi, const std::string& label);
  /// `downward`: y grows downward (image rows), as in an image-plane plot.
  void SetY(double lo, double hi, const std::string& label, bool downward = false);
  /// Widens one range so a unit is as long in x as in y (maps, image planes).
  void EqualAspect();
  /// Draws the frame, grid, ticks and labels, then clips to the data area
  /// until Legend(), ColorBar() or str().
  void Frame(bool grid = true);

  Svg::P At(double x, double y) const;
  Svg::P At(const Eigen::Vector2d& p) const { return At(p.x(), p.y()); }
  double PxPerUnitX() const { return size_.x() / (x_hi_ - x_lo_); }
  Svg& svg() { return svg_; }

  /// A vertical colour bar in the right margin, `lo` … `hi`, with ticks and a label.
  void ColorBar(double lo, double hi, const std::string& label,
                const std::function<cv::Scalar(double)>& colour_of);
  struct LegendEntry {
    std::string text, colour;
    Shape shape = Shape::kDisc;
  };
  /// A legend in the right margin (size it with LegendWidth()).
  void Legend(const std::vector<LegendEntry>& entries);
  static double LegendWidth(const std::vector<LegendEntry>& entries);

  std::string str();

 private:
  void Unclip();

  Svg svg_;
  std::string title_, x_label_, y_label_;
  Svg::P corner_, size_;  // the data area
  double x_lo_ = 0, x_hi_ = 1, y_lo_ = 0, y_hi_ = 1;
  bool y_down_ = false, clipped_ = false;
};

}  // namespace handeye::report
