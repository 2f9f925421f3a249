// SPDX-License-Identifier: GPL-2.0-or-later
// The report's plotting library (report_plot.h).
#include "report_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace handeye::report {
namespace {

const cv::Scalar kInk(40, 40, 40);
const cv::Scalar kGrid(225, 225, 225);
const cv::Scalar kFrame(120, 120, 120);
const cv::Scalar kWhite(255, 255, 255);
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
  auto polygon = [&](const std::vector<cv::Point2d>& corners, bool filled) {
    std::vector<cv::Point> pts;
    for (const auto& p : corners) pts.push_back(Fixed(c.x + p.x, c.y + p.y));
    if (filled)
      cv::fillPoly(*image, std::vector<std::vector<cv::Point>>{pts}, color, cv::LINE_AA, kShift);
    else
      cv::polylines(*image, std::vector<std::vector<cv::Point>>{pts}, true, color, thickness,
                    cv::LINE_AA, kShift);
  };
  switch (marker) {
    case Marker::kCircle:
      cv::circle(*image, Fixed(c), static_cast<int>(std::lround(r * kSubpixel)), color, thickness,
                 cv::LINE_AA, kShift);
      break;
    case Marker::kDisc:
      cv::circle(*image, Fixed(c), static_cast<int>(std::lround(r * kSubpixel)), color, cv::FILLED,
                 cv::LINE_AA, kShift);
      break;
    case Marker::kSquare:
      polygon({{-r, -r}, {r, -r}, {r, r}, {-r, r}}, true);
      break;
    case Marker::kTriangle:
      polygon({{0, -r}, {r * 0.9, r * 0.65}, {-r * 0.9, r * 0.65}}, true);
      break;
    case Marker::kDiamond:
      polygon({{0, -r}, {r, 0}, {0, r}, {-r, 0}}, false);
      break;
    case Marker::kCross:
      line(-r * 0.75, -r * 0.75, r * 0.75, r * 0.75);
      line(-r * 0.75, r * 0.75, r * 0.75, -r * 0.75);
      break;
    case Marker::kPlus:
      line(-r, 0, r, 0);
      line(0, -r, 0, r);
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

void DrawTextVertical(cv::Mat* image, const std::string& text, const cv::Point2d& centre,
                      double height, const cv::Scalar& color) {
  const cv::Size size = TextSize(text, height);
  const int pad = static_cast<int>(std::ceil(height * 0.6));
  cv::Mat patch(size.height + 2 * pad, size.width + 2 * pad, image->type(), kWhite);
  DrawText(&patch, text, {double(pad), double(pad)}, height, color);
  cv::rotate(patch, patch, cv::ROTATE_90_COUNTERCLOCKWISE);
  cv::Rect where(static_cast<int>(centre.x - patch.cols / 2.0),
                 static_cast<int>(centre.y - patch.rows / 2.0), patch.cols, patch.rows);
  where &= cv::Rect(0, 0, image->cols, image->rows);
  if (where.empty()) return;
  // Dark text on white: the darker of the two keeps both the text and what was there.
  cv::Mat target = (*image)(where);
  cv::min(target, patch(cv::Rect(0, 0, where.width, where.height)), target);
}

std::vector<double> NiceTicks(double lo, double hi, int count, double* step_out) {
  std::vector<double> ticks;
  if (!(hi > lo) || count < 1) return ticks;
  const double raw = (hi - lo) / count;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10 * decade;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * decade >= raw) {
      step = m * decade;
      break;
    }
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step)
    ticks.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
  if (step_out) *step_out = step;
  return ticks;
}

std::string TickLabel(double value, double step) {
  int decimals = 0;
  while (decimals < 6 &&
         std::abs(step * std::pow(10.0, decimals) - std::round(step * std::pow(10.0, decimals))) >
             1e-6 * step * std::pow(10.0, decimals))
    ++decimals;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  std::string s = buf;
  if (s == "-0") s = "0";
  return s;
}

Plot::Plot(int width, int height, const std::string& title, int right_margin)
    : image_(height, width, CV_8UC3, kWhite), title_(title) {
  const int left = 78, top = title.empty() ? 14 : 38, bottom = 52;
  area_ = cv::Rect(left, top, std::max(10, width - left - right_margin),
                   std::max(10, height - top - bottom));
}

void Plot::SetX(double lo, double hi, const std::string& label) {
  x_lo_ = lo;
  x_hi_ = hi > lo ? hi : lo + 1;
  x_label_ = label;
}

void Plot::SetY(double lo, double hi, const std::string& label, bool downward) {
  y_lo_ = lo;
  y_hi_ = hi > lo ? hi : lo + 1;
  y_label_ = label;
  y_down_ = downward;
}

void Plot::EqualAspect() {
  const double sx = area_.width / (x_hi_ - x_lo_), sy = area_.height / (y_hi_ - y_lo_);
  if (sx > sy) {
    const double grow = (area_.width / sy - (x_hi_ - x_lo_)) / 2;
    x_lo_ -= grow;
    x_hi_ += grow;
  } else {
    const double grow = (area_.height / sx - (y_hi_ - y_lo_)) / 2;
    y_lo_ -= grow;
    y_hi_ += grow;
  }
}

cv::Point2d Plot::AreaPx(double x, double y) const {
  const double u = (x - x_lo_) / (x_hi_ - x_lo_) * area_.width - 0.5;
  const double f = (y - y_lo_) / (y_hi_ - y_lo_) * area_.height;
  return {u, y_down_ ? f - 0.5 : area_.height - 0.5 - f};
}

cv::Point2d Plot::Px(double x, double y) const {
  const cv::Point2d p = AreaPx(x, y);
  return {p.x + area_.x, p.y + area_.y};
}

void Plot::DrawFrame(bool grid) {
  const double tick_h = 11, label_h = 12.5;
  double step = 1;
  const auto x_ticks = NiceTicks(x_lo_, x_hi_, std::max(2, area_.width / 90), &step);
  const double x_step = step;
  const auto y_ticks = NiceTicks(y_lo_, y_hi_, std::max(2, area_.height / 60), &step);
  const double y_step = step;
  cv::Mat area = Area();
  if (grid) {
    for (double x : x_ticks) {
      const cv::Point2d p = AreaPx(x, y_lo_);
      cv::line(area, Fixed(p.x, 0), Fixed(p.x, area_.height), kGrid, 1, cv::LINE_AA, kShift);
    }
    for (double y : y_ticks) {
      const cv::Point2d p = AreaPx(x_lo_, y);
      cv::line(area, Fixed(0, p.y), Fixed(area_.width, p.y), kGrid, 1, cv::LINE_AA, kShift);
    }
  }
  cv::rectangle(image_, area_, kFrame, 1);
  const double bottom = area_.y + area_.height;
  for (double x : x_ticks) {
    const cv::Point2d p = Px(x, y_lo_);
    cv::line(image_, Fixed(p.x, bottom), Fixed(p.x, bottom + 5), kFrame, 1, cv::LINE_AA, kShift);
    DrawText(&image_, TickLabel(x, x_step), {p.x, bottom + 9}, tick_h * 0.85, kInk, {0.5, 0});
  }
  for (double y : y_ticks) {
    const cv::Point2d p = Px(x_lo_, y);
    cv::line(image_, Fixed(area_.x - 5, p.y), Fixed(area_.x, p.y), kFrame, 1, cv::LINE_AA, kShift);
    DrawText(&image_, TickLabel(y, y_step), {area_.x - 8.0, p.y}, tick_h * 0.85, kInk, {1, 0.5});
  }
  if (!x_label_.empty())
    DrawText(&image_, x_label_, {area_.x + area_.width / 2.0, bottom + 30}, label_h * 0.9, kInk,
             {0.5, 0});
  if (!y_label_.empty())
    DrawTextVertical(&image_, y_label_, {16, area_.y + area_.height / 2.0}, label_h * 0.9, kInk);
  if (!title_.empty())
    DrawText(&image_, title_, {area_.x + 0.0, 12}, 14, cv::Scalar(20, 20, 20), {0, 0}, 1);
}

void Plot::Line(const std::vector<Eigen::Vector2d>& points, const cv::Scalar& color,
                int thickness) {
  if (points.size() < 2) return;
  std::vector<cv::Point> pts;
  for (const auto& p : points) pts.push_back(Fixed(AreaPx(p.x(), p.y())));
  cv::Mat area = Area();
  cv::polylines(area, std::vector<std::vector<cv::Point>>{pts}, false, color, thickness,
                cv::LINE_AA, kShift);
}

void Plot::DashedLine(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const cv::Scalar& color) {
  const cv::Point2d pa = AreaPx(a.x(), a.y()), pb = AreaPx(b.x(), b.y());
  const double len = std::hypot(pb.x - pa.x, pb.y - pa.y);
  const int dashes = std::max(1, static_cast<int>(len / 8));
  cv::Mat area = Area();
  for (int i = 0; i < dashes; i += 2) {
    const double s0 = double(i) / dashes, s1 = double(i + 1) / dashes;
    cv::line(area, Fixed(pa + s0 * (pb - pa)), Fixed(pa + s1 * (pb - pa)), color, 1, cv::LINE_AA,
             kShift);
  }
}

void Plot::Point(const Eigen::Vector2d& p, Marker marker, double size, const cv::Scalar& color,
                 int thickness) {
  cv::Mat area = Area();
  DrawMarker(&area, AreaPx(p.x(), p.y()), marker, size, color, thickness);
}

void Plot::Arrow(const Eigen::Vector2d& from, const Eigen::Vector2d& to, const cv::Scalar& color,
                 int thickness, double head) {
  cv::Mat area = Area();
  DrawArrow(&area, AreaPx(from.x(), from.y()), AreaPx(to.x(), to.y()), color, thickness, head);
}

void Plot::Bar(double x0, double x1, double height, const cv::Scalar& fill) {
  const cv::Point2d a = AreaPx(x0, 0), b = AreaPx(x1, height);
  cv::Mat area = Area();
  const cv::Rect bar(cv::Point(static_cast<int>(std::lround(std::min(a.x, b.x) + 0.5)),
                               static_cast<int>(std::lround(std::min(a.y, b.y) + 0.5))),
                     cv::Point(static_cast<int>(std::lround(std::max(a.x, b.x) + 0.5)),
                               static_cast<int>(std::lround(std::max(a.y, b.y) + 0.5))));
  cv::rectangle(area, bar, fill, cv::FILLED);
  cv::rectangle(area, bar, fill * 0.7, 1);
}

void Plot::Label(const Eigen::Vector2d& p, const std::string& text, const cv::Scalar& color,
                 double dx, double dy, Align align, double height) {
  const cv::Point2d at = Px(p.x(), p.y());
  DrawText(&image_, text, {at.x + dx, at.y + dy}, height, color, align);
}

void Plot::ColorBar(double lo, double hi, const std::string& label,
                    const std::function<cv::Scalar(double)>& color_of) {
  const int x0 = area_.x + area_.width + 18, width = 14;
  const int y0 = area_.y + 10, height = area_.height - 20;
  for (int i = 0; i < height; ++i) {
    const double v = hi - (hi - lo) * (i + 0.5) / height;
    cv::line(image_, {x0, y0 + i}, {x0 + width - 1, y0 + i}, color_of(v), 1);
  }
  cv::rectangle(image_, cv::Rect(x0, y0, width, height), kFrame, 1);
  double step = 1;
  for (double v : NiceTicks(lo, hi, 5, &step)) {
    const double y = y0 + (hi - v) / (hi - lo) * height;
    cv::line(image_, Fixed(x0 + width, y), Fixed(x0 + width + 4, y), kFrame, 1, cv::LINE_AA,
             kShift);
    DrawText(&image_, TickLabel(v, step), {x0 + width + 7.0, y}, 9.5, kInk, {0, 0.5});
  }
  DrawTextVertical(&image_, label, {x0 + width + 46.0, y0 + height / 2.0}, 11, kInk);
}

constexpr double kLegendText = 11;

int Plot::LegendWidth(const std::vector<LegendEntry>& entries) {
  int text_w = 0;
  for (const auto& e : entries) text_w = std::max(text_w, TextSize(e.text, kLegendText).width);
  return text_w + 40;
}

void Plot::Legend(const std::vector<LegendEntry>& entries, Place place) {
  if (entries.empty()) return;
  const double h = kLegendText, row = 18;
  const int box_w = LegendWidth(entries), box_h = static_cast<int>(row * entries.size() + 10);
  const int x = place == Place::kInsideLeft    ? area_.x + 8
                : place == Place::kInsideRight ? area_.x + area_.width - box_w - 8
                                               : area_.x + area_.width + 12;
  const int y = place == Place::kMargin ? area_.y : area_.y + 8;
  cv::Mat box = image_(cv::Rect(x, y, box_w, box_h) & cv::Rect(0, 0, image_.cols, image_.rows));
  box = 0.15 * box + 0.85 * cv::Scalar(255, 255, 255);
  cv::rectangle(image_, cv::Rect(x, y, box_w, box_h), kFrame, 1);
  for (size_t i = 0; i < entries.size(); ++i) {
    const double cy = y + 5 + row * (i + 0.5);
    if (entries[i].line)
      cv::line(image_, Fixed(x + 6, cy), Fixed(x + 26, cy), entries[i].color, 2, cv::LINE_AA,
               kShift);
    else
      DrawMarker(&image_, {x + 16.0, cy}, entries[i].marker, 9, entries[i].color, 2);
    DrawText(&image_, entries[i].text, {x + 32.0, cy}, h, kInk, {0, 0.5});
  }
}

}  // namespace handeye::report
