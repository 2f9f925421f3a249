// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The report's plots as SVG written inline into index.html: vector, any
// UTF-8 text (°, ×, −), axes with ticks and labels. Text is escaped, numbers
// are written the same in every locale, and an element with a number that is
// not finite is left out (a NaN in the data leaves a gap, never broken markup).

#include <Eigen/Core>
#include <functional>
#include <opencv2/core/types.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace handeye::report {

/// An SVG colour ("#rrggbb") of an OpenCV BGR colour.
std::string Hex(const cv::Scalar& bgr);

/// An attribute of an SVG element: a number or text.
using Attribute = std::pair<const char*, std::variant<double, std::string>>;

enum class Shape { kRing, kDisc, kSquare, kTriangle, kDiamond, kCross };

/// SVG elements one after another, in drawing coordinates (CSS pixels, y down).
class Svg {
 public:
  using P = Eigen::Vector2d;
  /// `title` is the drawing's accessible name.
  Svg(double width, double height, const std::string& title);

  /// <tag attributes/>, or <tag attributes>text</tag> when there is text.
  /// Text is escaped; the element is left out when a number is not finite.
  void Add(const char* tag, std::vector<Attribute> attributes, const std::string& text = "");
  /// A polyline with `extra` attributes, broken where a point is not finite.
  void Line(const std::vector<P>& points, const std::string& colour, double width = 1,
            const std::vector<Attribute>& extra = {});
  void Rect(const P& corner, const P& opposite, const std::string& fill,
            const std::string& stroke = "none");
  void Mark(const P& at, Shape shape, double size, const std::string& colour, double width = 1.5);
  void Arrow(const P& from, const P& to, const std::string& colour, double width, double head);
  /// Text with its vertical middle at `at`; `anchor`: start, middle or end;
  /// `turned`: rotated 90° counter-clockwise about `at`.
  void Text(const P& at, const std::string& text, double size, const std::string& colour,
            const char* anchor = "start", bool turned = false);
  /// What follows is clipped to the rectangle until EndClip().
  void BeginClip(const P& corner, const P& size);
  void EndClip() { out_ << "</svg>\n"; }
  std::string str() const { return out_.str() + "</svg>\n"; }

 private:
  std::ostringstream out_;
};

/// Ticks for [lo, hi]: multiples of a 1/2/2.5/5 × 10^k step, about `count` of them.
std::vector<double> NiceTicks(double lo, double hi, int count, double* step = nullptr);

/// One axis of a plot: its range and label.
struct Axis {
  double lo = 0, hi = 1;
  std::string label;
};

/// A 2-D plot on an Svg: a frame with grid, ticks, axis labels and a title
/// around a data area; At() maps data to drawing coordinates.
class SvgPlot {
 public:
  /// `right_margin` leaves room for a colour bar or a legend.
  SvgPlot(double width, double height, const std::string& title, double right_margin = 20);

  std::string title;  ///< what Frame() writes above the data area
  Axis x, y;          ///< a range that is empty or not finite becomes [0, 1]
  bool y_down = false;  ///< y grows downward (image rows), as in an image plane
  Svg svg;

  /// Widens one range so a unit is as long in x as in y (maps, image planes).
  void EqualAspect();
  /// Draws the frame, grid, ticks and labels, then clips to the data area
  /// until ColorBar(), Legend() or str().
  void Frame(bool grid = true);
  Svg::P At(double u, double v) const;
  Svg::P At(const Eigen::Vector2d& p) const { return At(p.x(), p.y()); }
  double PxPerUnitX() const { return size_.x() / (x.hi - x.lo); }

  /// A vertical colour bar in the right margin, `lo` … `hi`, with ticks and a label.
  void ColorBar(double lo, double hi, const std::string& label,
                const std::function<cv::Scalar(double)>& colour_of);
  struct LegendEntry {
    std::string text, colour;
    Shape shape = Shape::kDisc;
  };
  /// A legend in the right margin, LegendWidth() wide.
  void Legend(const std::vector<LegendEntry>& entries);
  static double LegendWidth(const std::vector<LegendEntry>& entries);

  std::string str();

 private:
  void Unclip();

  Svg::P corner_, size_;  // the data area
  bool clipped_ = false;
};

}  // namespace handeye::report
