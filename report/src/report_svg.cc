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

void Sanitise(Axis* axis) {
  if (!(std::isfinite(axis->lo) && std::isfinite(axis->hi) && axis->hi > axis->lo)) {
    axis->lo = 0;
    axis->hi = 1;
  }
}

}  // namespace

std::string Hex(const cv::Scalar& bgr) {
  auto channel = [](double v) { return std::isfinite(v) ? int(std::clamp(v, 0.0, 255.0)) : 0; };
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

void Svg::Add(const char* tag, std::vector<Attribute> attributes, const std::string& text) {
  std::string element = std::string("<") + tag;
  for (const auto& [name, value] : attributes) {
    const double* number = std::get_if<double>(&value);
    if (number && !std::isfinite(*number)) return;
    element += std::string(" ") + name + "=\"" + (number ? N(*number) : Escape(std::get<1>(value))) + "\"";
  }
  out_ << element << (text.empty() ? "/>\n" : ">" + Escape(text) + "</" + tag + ">\n");
}

void Svg::Line(const std::vector<P>& points, const std::string& colour, double width,
               const std::vector<Attribute>& extra) {
  for (auto p = points.begin(); p != points.end();) {
    std::string run;  // the points up to the next one that is not finite
    int count = 0;
    for (; p != points.end() && p->allFinite(); ++p, ++count) run += N(p->x()) + "," + N(p->y()) + " ";
    if (count >= 2) {
      // `extra` first; a default only where it names no value (no attribute twice).
      std::vector<Attribute> attributes = extra;
      for (Attribute a : std::vector<Attribute>{
               {"fill", "none"}, {"stroke", colour}, {"stroke-width", width}, {"points", run}})
        if (std::none_of(extra.begin(), extra.end(), [&](const Attribute& e) {
              return std::string(e.first) == a.first;
            }))
          attributes.push_back(a);
      Add("polyline", attributes);
    }
    if (p != points.end()) ++p;
  }
}

void Svg::Rect(const P& corner, const P& opposite, const std::string& fill,
               const std::string& stroke) {
  const P lo = corner.cwiseMin(opposite), size = (opposite - corner).cwiseAbs();
  Add("rect", {{"x", lo.x()}, {"y", lo.y()}, {"width", size.x()}, {"height", size.y()},
               {"fill", fill}, {"stroke", stroke}});
}

void Svg::Mark(const P& at, Shape shape, double size, const std::string& colour, double width) {
  const double r = size / 2;
  auto outline = [&](std::vector<P> offsets) {
    for (P& o : offsets) o = at + r * o;
    return offsets;
  };
  switch (shape) {
    case Shape::kRing:
      Add("circle", {{"cx", at.x()}, {"cy", at.y()}, {"r", r}, {"fill", "none"}, {"stroke", colour},
                     {"stroke-width", width}});
      break;
    case Shape::kDisc:
      Add("circle", {{"cx", at.x()}, {"cy", at.y()}, {"r", r}, {"fill", colour}});
      break;
    case Shape::kSquare:
      Rect(at - P(r, r), at + P(r, r), colour);
      break;
    case Shape::kTriangle:  // a closed, filled polyline
      Line(outline({{0, -1}, {0.9, 0.65}, {-0.9, 0.65}, {0, -1}}), colour, 1, {{"fill", colour}});
      break;
    case Shape::kDiamond:
      Line(outline({{0, -1}, {1, 0}, {0, 1}, {-1, 0}, {0, -1}}), colour, width);
      break;
    case Shape::kCross:
      Line(outline({{-0.75, -0.75}, {0.75, 0.75}}), colour, width);
      Line(outline({{-0.75, 0.75}, {0.75, -0.75}}), colour, width);
      break;
  }
}

void Svg::Arrow(const P& from, const P& to, const std::string& colour, double width,
                double head) {
  const double length = (to - from).norm();
  if (!(length > 1e-9 && std::isfinite(length))) return;
  const P u = (to - from) / length, n(-u.y(), u.x());
  const double h = std::min(head, 0.5 * length + 2);
  Line({from, to - 0.5 * h * u}, colour, width);
  Line({to, to - h * u + 0.45 * h * n, to - h * u - 0.45 * h * n, to}, colour, 1,
       {{"fill", colour}});
}

void Svg::Text(const P& at, const std::string& text, double size, const std::string& colour,
               const char* anchor, bool turned) {
  std::vector<Attribute> attributes = {{"x", at.x()},           {"y", at.y()},
                                       {"dy", "0.35em"},        {"font-size", size},
                                       {"fill", colour},        {"text-anchor", anchor}};
  if (turned && at.allFinite())
    attributes.push_back({"transform", "rotate(-90 " + N(at.x()) + " " + N(at.y()) + ")"});
  if (!text.empty()) Add("text", attributes, text);
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
  for (double m : {5.0, 2.5, 2.0, 1.0})
    if (m * decade >= raw) step = m * decade;
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step)
    ticks.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
  if (step_out) *step_out = step;
  return ticks;
}

SvgPlot::SvgPlot(double width, double height, const std::string& title_text, double right_margin)
    : title(title_text), svg(width, height, title_text) {
  const double left = 72, top = title.empty() ? 14 : 36, bottom = 50;
  corner_ = {left, top};
  size_ = {std::max(10.0, width - left - right_margin), std::max(10.0, height - top - bottom)};
}

void SvgPlot::EqualAspect() {
  Sanitise(&x);
  Sanitise(&y);
  const double sx = size_.x() / (x.hi - x.lo), sy = size_.y() / (y.hi - y.lo);
  Axis& wider = sx > sy ? x : y;
  const double grow = (sx > sy ? size_.x() / sy : size_.y() / sx) - (wider.hi - wider.lo);
  wider.lo -= grow / 2;
  wider.hi += grow / 2;
}

Svg::P SvgPlot::At(double u, double v) const {
  const double f = (v - y.lo) / (y.hi - y.lo) * size_.y();
  return {corner_.x() + (u - x.lo) / (x.hi - x.lo) * size_.x(),
          y_down ? corner_.y() + f : corner_.y() + size_.y() - f};
}

void SvgPlot::Frame(bool grid) {
  Sanitise(&x);
  Sanitise(&y);
  double x_step = 1, y_step = 1;
  const auto x_ticks = NiceTicks(x.lo, x.hi, std::max(2, int(size_.x() / 90)), &x_step);
  const auto y_ticks = NiceTicks(y.lo, y.hi, std::max(2, int(size_.y() / 60)), &y_step);
  if (grid) {
    for (double u : x_ticks) svg.Line({At(u, y.lo), At(u, y.hi)}, "#e1e1e1");
    for (double v : y_ticks) svg.Line({At(x.lo, v), At(x.hi, v)}, "#e1e1e1");
  }
  svg.Rect(corner_, corner_ + size_, "none", kFrameColour);
  const double left = corner_.x(), bottom = corner_.y() + size_.y();
  for (double u : x_ticks) {
    const double at = At(u, y.lo).x();
    svg.Line({{at, bottom}, {at, bottom + 5}}, kFrameColour);
    svg.Text({at, bottom + 14}, TickLabel(u, x_step), 11, kInk, "middle");
  }
  for (double v : y_ticks) {
    const double at = At(x.lo, v).y();
    svg.Line({{left - 5, at}, {left, at}}, kFrameColour);
    svg.Text({left - 8, at}, TickLabel(v, y_step), 11, kInk, "end");
  }
  svg.Text({left + size_.x() / 2, bottom + 36}, x.label, 12.5, kInk, "middle");
  svg.Text({16, corner_.y() + size_.y() / 2}, y.label, 12.5, kInk, "middle", true);
  svg.Text({left, 16}, title, 14, "#141414");
  svg.BeginClip(corner_, size_);
  clipped_ = true;
}

void SvgPlot::Unclip() {
  if (clipped_) svg.EndClip();
  clipped_ = false;
}

void SvgPlot::ColorBar(double lo, double hi, const std::string& label,
                       const std::function<cv::Scalar(double)>& colour_of) {
  Unclip();
  if (!(hi > lo && std::isfinite(hi - lo))) return;
  const double x0 = corner_.x() + size_.x() + 18, width = 14;
  const double y0 = corner_.y() + 10, height = size_.y() - 20;
  constexpr int kSteps = 48;
  for (int i = 0; i < kSteps; ++i)  // each band overlaps the next, so no seams show
    svg.Rect({x0, y0 + height * i / kSteps}, {x0 + width, y0 + height * (i + 1.5) / kSteps},
             Hex(colour_of(hi - (hi - lo) * (i + 0.5) / kSteps)));
  svg.Rect({x0, y0}, {x0 + width, y0 + height + height / (2.0 * kSteps)}, "none", kFrameColour);
  double step = 1;
  for (double v : NiceTicks(lo, hi, 5, &step)) {
    const double at = y0 + (hi - v) / (hi - lo) * height;
    svg.Line({{x0 + width, at}, {x0 + width + 4, at}}, kFrameColour);
    svg.Text({x0 + width + 7, at}, TickLabel(v, step), 10, kInk);
  }
  svg.Text({x0 + width + 48, y0 + height / 2}, label, 11, kInk, "middle", true);
}

double SvgPlot::LegendWidth(const std::vector<LegendEntry>& entries) {
  // At about a sans-serif font's mean advance per character (UTF-8
  // continuation bytes, 10xxxxxx, are no characters).
  std::ptrdiff_t chars = 0;
  for (const LegendEntry& e : entries)
    chars = std::max(chars, std::count_if(e.text.begin(), e.text.end(), [](char c) {
                       return (static_cast<unsigned char>(c) & 0xC0) != 0x80;
                     }));
  return 0.6 * 11 * static_cast<double>(chars) + 40;
}

void SvgPlot::Legend(const std::vector<LegendEntry>& entries) {
  Unclip();
  const double row = 18, left = corner_.x() + size_.x() + 12, top = corner_.y();
  svg.Rect({left, top}, {left + LegendWidth(entries), top + row * entries.size() + 10}, "#fbfbfb",
           kFrameColour);
  for (size_t i = 0; i < entries.size(); ++i) {
    const double mid = top + 5 + row * (i + 0.5);
    svg.Mark({left + 16, mid}, entries[i].shape, 9, entries[i].colour, 2);
    svg.Text({left + 32, mid}, entries[i].text, 11, kInk);
  }
}

std::string SvgPlot::str() {
  Unclip();
  return svg.str();
}

}  // namespace handeye::report
