// SPDX-License-Identifier: GPL-2.0-or-later
// The report's SVG writer and plot frame (report_svg.h).
#include "report_svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "report_html.h"

namespace handeye::report {
namespace {

const char* kInk = "#282828";
const char* kFrameColour = "#787878";

// Coordinates to a tenth of a CSS pixel: finer than any screen shows.
std::string N(double value) { return Num(value, 1); }

std::string Points(const std::vector<Svg::P>& points) {
  std::string out;
  for (const Svg::P& p : points) out += N(p.x()) + "," + N(p.y()) + " ";
  out.pop_back();
  return out;
}

bool AllFinite(const std::vector<Svg::P>& points) {
  return std::all_of(points.begin(), points.end(), [](const Svg::P& p) { return p.allFinite(); });
}

}  // namespace

std::string Hex(const cv::Scalar& bgr) {
  auto channel = [](double v) { return static_cast<int>(std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 255.0)); };
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", channel(bgr[2]), channel(bgr[1]), channel(bgr[0]));
  return buf;
}

Svg::Svg(double width, double height, const std::string& title) {
  out_ << "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"plot\" width=\"" << N(width)
       << "\" height=\"" << N(height) << "\" viewBox=\"0 0 " << N(width) << " " << N(height)
       << "\" role=\"img\" font-family=\"DejaVu Sans, Arial, sans-serif\"><title>"
       << Escape(title) << "</title>\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
}

void Svg::Line(const std::vector<P>& points, const std::string& colour, double width,
               const std::string& style) {
  std::vector<P> run;
  auto flush = [&] {
    if (run.size() >= 2)
      out_ << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"" << N(width)
           << "\"" << (style.empty() ? "" : " ") << style << " points=\"" << Points(run)
           << "\"/>\n";
    run.clear();
  };
  for (const P& p : points) {
    if (p.allFinite())
      run.push_back(p);
    else
      flush();
  }
  flush();
}

void Svg::Polygon(const std::vector<P>& points, const std::string& fill) {
  if (points.size() < 3 || !AllFinite(points)) return;
  out_ << "<polygon fill=\"" << fill << "\" points=\"" << Points(points) << "\"/>\n";
}

void Svg::Rect(const P& corner, const P& opposite, const std::string& fill,
               const std::string& stroke) {
  if (!corner.allFinite() || !opposite.allFinite()) return;
  const P lo = corner.cwiseMin(opposite), size = (opposite - corner).cwiseAbs();
  out_ << "<rect x=\"" << N(lo.x()) << "\" y=\"" << N(lo.y()) << "\" width=\"" << N(size.x())
       << "\" height=\"" << N(size.y()) << "\" fill=\"" << fill << "\" stroke=\"" << stroke
       << "\"/>\n";
}

void Svg::Mark(const P& at, Shape shape, double size, const std::string& colour, double width) {
  if (!at.allFinite()) return;
  const double r = size / 2;
  auto at_plus = [&](std::initializer_list<P> offsets) {
    std::vector<P> out;
    for (const P& o : offsets) out.push_back(at + r * o);
    return out;
  };
  switch (shape) {
    case Shape::kRing:
    case Shape::kDisc:
      out_ << "<circle cx=\"" << N(at.x()) << "\" cy=\"" << N(at.y()) << "\" r=\"" << N(r)
           << (shape == Shape::kDisc ? "\" fill=\"" + colour + "\"/>\n"
                                     : "\" fill=\"none\" stroke=\"" + colour +
                                           "\" stroke-width=\"" + N(width) + "\"/>\n");
      break;
    case Shape::kSquare:
      Rect(at - P(r, r), at + P(r, r), colour);
      break;
    case Shape::kTriangle:
      Polygon(at_plus({{0, -1}, {0.9, 0.65}, {-0.9, 0.65}}), colour);
      break;
    case Shape::kDiamond:
      Line(at_plus({{0, -1}, {1, 0}, {0, 1}, {-1, 0}, {0, -1}}), colour, width);
      break;
    case Shape::kCross:
      Line(at_plus({{-0.75, -0.75}, {0.75, 0.75}}), colour, width);
      Line(at_plus({{-0.75, 0.75}, {0.75, -0.75}}), colour, width);
      break;
  }
}

void Svg::Arrow(const P& from, const P& to, const std::string& colour, double width,
                double head) {
  const double length = (to - from).norm();
  if (!(length > 1e-9) || !std::isfinite(length)) return;
  const P u = (to - from) / length, n(-u.y(), u.x());
  const double h = std::min(head, 0.5 * length + 2);
  Line({from, to - 0.5 * h * u}, colour, width);
  Polygon({to, to - h * u + 0.45 * h * n, to - h * u - 0.45 * h * n}, colour);
}

void Svg::Text(const P& at, const std::string& text, double size, const std::string& colour,
               const char* anchor, bool turned) {
  if (!at.allFinite() || text.empty()) return;
  out_ << "<text x=\"" << N(at.x()) << "\" y=\"" << N(at.y()) << "\" dy=\"0.35em\" font-size=\""
       << N(size) << "\" fill=\"" << colour << "\" text-anchor=\"" << anchor << "\"";
  if (turned) out_ << " transform=\"rotate(-90 " << N(at.x()) << " " << N(at.y()) << ")\"";
  out_ << ">" << Escape(text) << "</text>\n";
}

void Svg::BeginClip(const P& corner, const P& size) {
  out_ << "<svg x=\"" << N(corner.x()) << "\" y=\"" << N(corner.y()) << "\" width=\""
       << N(size.x()) << "\" height=\"" << N(size.y()) << "\" viewBox=\"" << N(corner.x()) << " "
       << N(corner.y()) << " " << N(size.x()) << " " << N(size.y()) << "\" overflow=\"hidden\">\n";
}

std::vector<double> NiceTicks(double lo, double hi, int count, double* step_out) {
  std::vector<double> ticks;
  if (!(hi > lo) || !std::isfinite(hi - lo) || count < 1) return ticks;
  const double raw = (hi - lo) / count;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10 * decade;
  for (double m : {1.0, 2.0, 2.5, 5.0})
    if (m * decade >= raw) {
      step = m * decade;
      break;
    }
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step)
    ticks.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
  if (step_out) *step_out = step;
  return ticks;
}

double TextWidth(const std::string& text, double size) {
  // Characters, not bytes (UTF-8 continuation bytes are 10xxxxxx), at about
  // the mean advance of a sans-serif font.
  const auto chars = std::count_if(text.begin(), text.end(),
                                   [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; });
  return 0.6 * size * static_cast<double>(chars);
}

SvgPlot::SvgPlot(double width, double height, const std::string& title, double right_margin)
    : svg_(width, height, title), title_(title) {
  const double left = 72, top = title.empty() ? 14 : 36, bottom = 50;
  corner_ = {left, top};
  size_ = {std::max(10.0, width - left - right_margin), std::max(10.0, height - top - bottom)};
}

void SvgPlot::SetX(double lo, double hi, const std::string& label) {
  const bool usable = std::isfinite(lo) && std::isfinite(hi) && hi > lo;
  x_lo_ = usable ? lo : 0;
  x_hi_ = usable ? hi : 1;
  x_label_ = label;
}

void SvgPlot::SetY(double lo, double hi, const std::string& label, bool downward) {
  const bool usable = std::isfinite(lo) && std::isfinite(hi) && hi > lo;
  y_lo_ = usable ? lo : 0;
  y_hi_ = usable ? hi : 1;
  y_label_ = label;
  y_down_ = downward;
}

void SvgPlot::EqualAspect() {
  const double sx = size_.x() / (x_hi_ - x_lo_), sy = size_.y() / (y_hi_ - y_lo_);
  double& lo = sx > sy ? x_lo_ : y_lo_;
  double& hi = sx > sy ? x_hi_ : y_hi_;
  const double grow = sx > sy ? (size_.x() / sy - (x_hi_ - x_lo_)) / 2
                              : (size_.y() / sx - (y_hi_ - y_lo_)) / 2;
  lo -= grow;
  hi += grow;
}

Svg::P SvgPlot::At(double x, double y) const {
  const double f = (y - y_lo_) / (y_hi_ - y_lo_) * size_.y();
  return {corner_.x() + (x - x_lo_) / (x_hi_ - x_lo_) * size_.x(),
          y_down_ ? corner_.y() + f : corner_.y() + size_.y() - f};
}

void SvgPlot::Frame(bool grid) {
  double x_step = 1, y_step = 1;
  const auto x_ticks = NiceTicks(x_lo_, x_hi_, std::max(2, int(size_.x() / 90)), &x_step);
  const auto y_ticks = NiceTicks(y_lo_, y_hi_, std::max(2, int(size_.y() / 60)), &y_step);
  if (grid) {
    for (double x : x_ticks) svg_.Line({At(x, y_lo_), At(x, y_hi_)}, "#e1e1e1");
    for (double y : y_ticks) svg_.Line({At(x_lo_, y), At(x_hi_, y)}, "#e1e1e1");
  }
  svg_.Rect(corner_, corner_ + size_, "none", kFrameColour);
  const double left = corner_.x(), bottom = corner_.y() + size_.y();
  for (double x : x_ticks) {
    const double u = At(x, y_lo_).x();
    svg_.Line({{u, bottom}, {u, bottom + 5}}, kFrameColour);
    svg_.Text({u, bottom + 14}, TickLabel(x, x_step), 11, kInk, "middle");
  }
  for (double y : y_ticks) {
    const double v = At(x_lo_, y).y();
    svg_.Line({{left - 5, v}, {left, v}}, kFrameColour);
    svg_.Text({left - 8, v}, TickLabel(y, y_step), 11, kInk, "end");
  }
  svg_.Text({left + size_.x() / 2, bottom + 36}, x_label_, 12.5, kInk, "middle");
  svg_.Text({16, corner_.y() + size_.y() / 2}, y_label_, 12.5, kInk, "middle", true);
  svg_.Text({left, 16}, title_, 14, "#141414");
  svg_.BeginClip(corner_, size_);
  clipped_ = true;
}

void SvgPlot::Unclip() {
  if (clipped_) svg_.EndClip();
  clipped_ = false;
}

void SvgPlot::ColorBar(double lo, double hi, const std::string& label,
                       const std::function<cv::Scalar(double)>& colour_of) {
  Unclip();
  if (!(hi > lo) || !std::isfinite(hi - lo)) return;
  const double x0 = corner_.x() + size_.x() + 18, width = 14;
  const double y0 = corner_.y() + 10, height = size_.y() - 20;
  constexpr int kSteps = 48;
  for (int i = 0; i < kSteps; ++i)  // each band overlaps the next, so no seams show
    svg_.Rect({x0, y0 + height * i / kSteps}, {x0 + width, y0 + height * (i + 1.5) / kSteps},
              Hex(colour_of(hi - (hi - lo) * (i + 0.5) / kSteps)));
  svg_.Rect({x0, y0}, {x0 + width, y0 + height + height / (2.0 * kSteps)}, "none", kFrameColour);
  double step = 1;
  for (double v : NiceTicks(lo, hi, 5, &step)) {
    const double y = y0 + (hi - v) / (hi - lo) * height;
    svg_.Line({{x0 + width, y}, {x0 + width + 4, y}}, kFrameColour);
    svg_.Text({x0 + width + 7, y}, TickLabel(v, step), 10, kInk);
  }
  svg_.Text({x0 + width + 48, y0 + height / 2}, label, 11, kInk, "middle", true);
}

double SvgPlot::LegendWidth(const std::vector<LegendEntry>& entries) {
  double text = 0;
  for (const LegendEntry& e : entries) text = std::max(text, TextWidth(e.text, 11));
  return text + 40;
}

void SvgPlot::Legend(const std::vector<LegendEntry>& entries) {
  Unclip();
  const double row = 18, x = corner_.x() + size_.x() + 12, y = corner_.y();
  svg_.Rect({x, y}, {x + LegendWidth(entries), y + row * entries.size() + 10}, "#fbfbfb",
            kFrameColour);
  for (size_t i = 0; i < entries.size(); ++i) {
    const double cy = y + 5 + row * (i + 0.5);
    svg_.Mark({x + 16, cy}, entries[i].shape, 9, entries[i].colour, 2);
    svg_.Text({x + 32, cy}, entries[i].text, 11, kInk);
  }
}

std::string SvgPlot::str() {
  Unclip();
  return svg_.str();
}

}  // namespace handeye::report
