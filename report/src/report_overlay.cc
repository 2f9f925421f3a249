// SPDX-License-Identifier: GPL-2.0-or-later
// Per-view overlays: the image (dimmed so marks stand out) with detected
// points, their reprojection through the calibrated chain, magnified residual
// vectors coloured by size, the cross-camera predictions, the target's outline
// and axes from the calibrated pose, a header and a legend.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "report_draw.h"
#include "report_html.h"
#include "report_internal.h"

namespace handeye::report {
namespace {

const cv::Scalar kDetected(255, 255, 0);     // cyan ring
const cv::Scalar kReprojected(255, 0, 255);  // magenta cross
const cv::Scalar kOutline(255, 190, 60);     // light blue
const cv::Scalar kAxisX(40, 40, 255), kAxisY(40, 200, 40), kAxisZ(255, 110, 30);
const cv::Scalar kPanel(30, 30, 30);
const cv::Scalar kText(245, 245, 245);
const cv::Scalar kBad(40, 40, 230), kWarn(0, 150, 255), kGood(90, 200, 90);
// Cross-camera predictions, per other camera: colours that read apart from
// the cyan rings and magenta crosses (and are not mistaken for them by a
// colour test: neither B ≈ G ≫ R nor B ≈ R ≫ G).
const cv::Scalar kCrossColors[] = {{255, 144, 30}, {255, 255, 255}, {180, 105, 255}, {0, 140, 255}};

void Darken(cv::Mat* image, const cv::Rect& rect, double keep) {
  const cv::Rect r = rect & cv::Rect(0, 0, image->cols, image->rows);
  if (r.empty()) return;
  cv::Mat roi = (*image)(r);
  roi = keep * roi + (1.0 - keep) * kPanel;
}

// Where an original image pixel lands in a drawing: the image itself, or a
// crop whose top-left pixel is `origin`, enlarged `zoom` times (as cv::resize
// maps pixel centres: (u + 0.5)·zoom − 0.5).
struct PixelMap {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  double zoom = 1;
  cv::Point2d operator()(const Eigen::Vector2d& p) const {
    return {(p.x() - origin.x() + 0.5) * zoom - 0.5, (p.y() - origin.y() + 0.5) * zoom - 0.5};
  }
};

// Draws the target-plane polyline through the pose and the lens model:
// straight edges on the target bend with distortion in the image.
void DrawTargetCurve(cv::Mat* image, const PixelMap& map, const Camera& camera,
                     const Eigen::Isometry3d& T_cam_target, const Eigen::Vector3d& a,
                     const Eigen::Vector3d& b, const cv::Scalar& color, int thickness) {
  constexpr int kSteps = 24;
  std::vector<cv::Point> run;
  auto flush = [&]() {
    if (run.size() >= 2)
      cv::polylines(*image, std::vector<std::vector<cv::Point>>{run}, false, color, thickness,
                    cv::LINE_AA, kShift);
    run.clear();
  };
  for (int i = 0; i <= kSteps; ++i) {
    const auto uv = camera.Project(T_cam_target * (a + (b - a) * (double(i) / kSteps)));
    if (!uv || !uv->allFinite() || uv->cwiseAbs().maxCoeff() > 1e5) {
      flush();
      continue;
    }
    run.push_back(Fixed(map(*uv)));
  }
  flush();
}

// The sheet's corners in the target frame, in order around it.
std::array<Eigen::Vector3d, 4> SheetCorners(const Target& target) {
  const Eigen::AlignedBox2d box = target.Extent();
  std::array<Eigen::Vector3d, 4> corners;
  const Eigen::AlignedBox2d::CornerType order[4] = {
      Eigen::AlignedBox2d::BottomLeft, Eigen::AlignedBox2d::BottomRight,
      Eigen::AlignedBox2d::TopRight, Eigen::AlignedBox2d::TopLeft};
  for (int i = 0; i < 4; ++i) corners[i] << box.corner(order[i]), 0.0;
  return corners;
}

void DrawTargetFrame(cv::Mat* image, const PixelMap& map, const Camera& camera,
                     const Target& target, const Eigen::Isometry3d& T, double ui) {
  const int thick = std::max(1, static_cast<int>(std::lround(2 * ui)));
  const auto c = SheetCorners(target);
  for (int i = 0; i < 4; ++i)
    DrawTargetCurve(image, map, camera, T, c[i], c[(i + 1) % 4], kOutline, thick);
  // Axes from the target origin, half the sheet's shorter side long.
  const double len = target.Extent().sizes().minCoeff() / 2.0;
  const std::pair<Eigen::Vector3d, cv::Scalar> axes[3] = {{Eigen::Vector3d(len, 0, 0), kAxisX},
                                                          {Eigen::Vector3d(0, len, 0), kAxisY},
                                                          {Eigen::Vector3d(0, 0, len), kAxisZ}};
  const char* names[3] = {"x", "y", "z"};
  const auto uv0 = camera.Project(T * Eigen::Vector3d::Zero());
  for (int i = 0; i < 3; ++i) {
    const auto uv1 = camera.Project(T * axes[i].first);
    if (!uv0 || !uv1) continue;
    const cv::Point2d p0 = map(*uv0), p1 = map(*uv1);
    DrawArrow(image, p0, p1, axes[i].second, thick + 1, 14 * ui);
    DrawText(image, names[i], p1 + (p1 - p0) * (10 * ui / std::max(1.0, cv::norm(p1 - p0))),
             16 * ui, axes[i].second, {0.5, 0.5}, thick);
  }
}

void DrawHeader(cv::Mat* image, const ReportModel& model, const ViewModel& view, double ui) {
  const Camera& camera = *model.cameras[view.camera].camera;
  const double h = 17 * ui, line = h * 1.9;
  const int thick = ui > 0.75 ? 2 : 1;
  std::string text = camera.name + "   pose " + view.observation->pose_id + " (" +
                     std::to_string(view.pose + 1) + "/" +
                     std::to_string(model.dataset->poses.size()) + ")   " +
                     std::to_string(view.observation->ids.size()) + " points";
  if (view.T_cam_target)
    text += "   RMS " + Num(view.rms_px, 3) + " px   max " + Num(view.max_px, 3) +
            " px";
  std::string status = "used by the solver";
  cv::Scalar color = kGood;
  if (!view.T_cam_target) {
    status = "camera not calibrated";
    color = kWarn;
  } else if (!view.used) {
    status = "REJECTED: " + view.rejected_because;
    color = kWarn;
  } else if (view.outlier) {
    status = "OUTLIER: down-weighted by the robust loss";
    color = kBad;
  }
  std::string cross;
  for (const CrossPrediction& c : view.cross)
    cross += (cross.empty() ? "predicted via " : "   via ") +
             model.cameras[c.other_camera].camera->name + ": RMS " + Num(c.rms_px, 3) +
             " px";
  // The status goes right of the first line when it fits, else on its own line.
  const double status_h = h * 0.9;
  const double status_x = image->cols - 12 * ui - TextSize(status, status_h, thick).width;
  const bool status_inline = status_x > TextSize(text, h, thick).width + 40 * ui;
  const int lines = 1 + (status_inline ? 0 : 1) + (cross.empty() ? 0 : 1);
  Darken(image, {0, 0, image->cols, static_cast<int>(std::lround(line * lines + 0.4 * h))}, 0.25);
  double y = 0.2 * h + line / 2;
  DrawText(image, text, {12 * ui, y}, h, kText, {0, 0.5}, thick);
  if (status_inline) {
    DrawText(image, status, {status_x, y}, status_h, color, {0, 0.5}, thick);
  } else {
    y += line;
    DrawText(image, status, {12 * ui, y}, status_h, color, {0, 0.5}, thick);
  }
  if (!cross.empty()) DrawText(image, cross, {12 * ui, y + line}, h * 0.85, kText, {0, 0.5}, 1);
  if (view.outlier || !view.used) {
    const int frame = std::max(2, static_cast<int>(std::lround(6 * ui)));
    cv::rectangle(*image, cv::Rect(0, 0, image->cols, image->rows), color, 2 * frame);
  }
}

void DrawLegend(cv::Mat* image, const ReportModel& model, const ViewModel& view,
                double magnification, double ui) {
  const double h = 13 * ui, row = 24 * ui, pad = 10 * ui;
  const int thick = ui > 0.75 ? 2 : 1;
  enum Kind { kRing, kCrossMark, kDiamondMark, kResidual, kScale, kAxes };
  struct Row {
    std::string text;
    Kind kind;
    cv::Scalar color;
    double height = 1;  // in rows
  };
  std::vector<Row> rows = {{"detected", kRing, kDetected},
                           {"reprojected through the calibrated chain", kCrossMark, kReprojected}};
  const std::string& name_k = model.cameras[view.camera].camera->name;
  for (size_t i = 0; i < view.cross.size(); ++i) {
    const std::string& name_t = model.cameras[view.cross[i].other_camera].camera->name;
    rows.push_back({"predicted via " + name_t + " (T_" + name_k + "_" + name_t + ")", kDiamondMark,
                    kCrossColors[i % 4]});
  }
  const double scale = model.residual_scale_max_px;
  const double bar_px = scale * magnification;
  rows.push_back({"residual x" + TickLabel(magnification, magnification) +
                      " (detected - reprojected): line = " + TickLabel(scale, scale / 10) + " px",
                  kResidual, ResidualColor(scale, scale)});
  rows.push_back({"residual size (px)", kScale, {}, 1.7});
  rows.push_back({"target outline and axes x, y, z (calibrated pose)", kAxes, kOutline});
  const double sample_w = std::max(40 * ui, bar_px + 6 * ui);
  double text_w = 0;
  for (const Row& r : rows) text_w = std::max<double>(text_w, TextSize(r.text, h, 1).width);
  double total_rows = 0;
  for (const Row& r : rows) total_rows += r.height;
  const double box_w = pad * 3 + sample_w + text_w;
  const double box_h = pad * 2 + row * total_rows;
  const double x0 = 12 * ui, y0 = image->rows - box_h - 12 * ui;
  Darken(image, cv::Rect(int(x0), int(y0), int(box_w), int(box_h)), 0.3);
  double y = y0 + pad;
  for (const Row& r : rows) {
    const double cy = y + row * 0.5;
    y += row * r.height;
    const cv::Point2d mark(x0 + pad + sample_w / 2, cy);
    const double tx = x0 + pad * 2 + sample_w;
    switch (r.kind) {
      case kRing:
        DrawMarker(image, mark, Marker::kCircle, 12 * ui, r.color, thick);
        break;
      case kCrossMark:
        DrawMarker(image, mark, Marker::kCross, 9 * ui, r.color, thick);
        break;
      case kDiamondMark:
        DrawMarker(image, mark, Marker::kDiamond, 11 * ui, r.color, 1);
        break;
      case kResidual:
        cv::line(*image, Fixed(x0 + pad, cy), Fixed(x0 + pad + bar_px, cy), r.color, thick,
                 cv::LINE_AA, kShift);
        break;
      case kScale: {
        // Colour scale of residual sizes over the sample column and part of
        // the text column, ticks below it, its name to its right.
        const double bx = x0 + pad, bw = sample_w + pad + 0.45 * text_w;
        for (int i = 0; i < static_cast<int>(bw); ++i)
          cv::line(*image, {int(bx) + i, int(cy - 6 * ui)}, {int(bx) + i, int(cy + 4 * ui)},
                   ResidualColor(scale * i / bw, scale), 1);
        for (int t = 0; t <= 4; ++t)
          DrawText(image, TickLabel(scale * t / 4, scale / 4), {bx + bw * t / 4, cy + 8 * ui},
                   h * 0.8, kText,
                   {t == 0   ? 0.0
                    : t == 4 ? 1.0
                             : 0.5,
                    0});
        DrawText(image, r.text, {bx + bw + 10 * ui, cy - 1 * ui}, h, kText, {0, 0.5});
        continue;
      }
      case kAxes:
        DrawArrow(image, {x0 + pad, cy + 7 * ui}, {x0 + pad + 16 * ui, cy + 7 * ui}, kAxisX, thick,
                  5 * ui);
        DrawArrow(image, {x0 + pad, cy + 7 * ui}, {x0 + pad, cy - 9 * ui}, kAxisY, thick, 5 * ui);
        DrawArrow(image, {x0 + pad, cy + 7 * ui}, {x0 + pad + 11 * ui, cy - 5 * ui}, kAxisZ, thick,
                  5 * ui);
        cv::line(*image, Fixed(x0 + pad + 22 * ui, cy), Fixed(x0 + pad + sample_w, cy), kOutline,
                 thick, cv::LINE_AA, kShift);
        break;
    }
    DrawText(image, r.text, {tx, cy}, h, kText, {0, 0.5});
  }
}

// Median distance from a detected point to its nearest neighbour (pixels):
// marks are sized from it so that dense or distant targets stay readable.
double PointSpacing(const std::vector<Eigen::Vector2d>& points) {
  std::vector<double> nearest;
  for (size_t i = 0; i < points.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < points.size(); ++j)
      if (j != i) best = std::min(best, (points[i] - points[j]).norm());
    if (std::isfinite(best)) nearest.push_back(best);
  }
  if (nearest.empty()) return std::numeric_limits<double>::infinity();
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  return nearest[nearest.size() / 2];
}

}  // namespace

cv::Scalar ResidualColor(double residual_px, double scale_max_px) {
  // Green (good) → yellow → red (at and above the scale's maximum), BGR.
  const double s = std::clamp(residual_px / scale_max_px, 0.0, 1.0);
  const cv::Scalar green(60, 190, 40), yellow(0, 220, 255), red(30, 30, 235);
  return s < 0.5 ? green + (yellow - green) * (s / 0.5)
                 : yellow + (red - yellow) * ((s - 0.5) / 0.5);
}

cv::Scalar CameraColor(int camera) {
  // Tableau 10 (BGR): distinct, print-safe and readable on white.
  static const cv::Scalar kPalette[] = {
      {180, 119, 31}, {14, 127, 255},  {44, 160, 44},   {40, 39, 214},  {189, 103, 148},
      {75, 86, 140},  {194, 119, 227}, {127, 127, 127}, {34, 189, 188}, {207, 190, 23}};
  return kPalette[camera % 10];
}

namespace {

// The marks of a view through `map` onto `image`; `clean` is `image` before
// any mark. Graphics under the marks (target frame, residual vectors,
// cross-camera predictions) are cleared around each detected point, so rings
// and crosses are drawn on the image alone: nothing hides them and their
// anti-aliased edges do not mix with other colours (which would shift where
// the eye, or a test, sees them).
void DrawMarks(cv::Mat* image, const cv::Mat& clean, const ReportModel& model,
               const ViewModel& view, const PixelMap& map, double ring, double magnification,
               double ui) {
  const Camera& camera = *model.cameras[view.camera].camera;
  const Observation& obs = *view.observation;
  const int thick = ui > 0.75 ? 2 : 1;
  const int mark_thick = ring >= 10 ? thick : 1;
  if (view.T_cam_target)
    DrawTargetFrame(image, map, camera, *model.dataset->target, *view.T_cam_target, ui);
  for (size_t i = 0; i < view.predicted_px.size(); ++i) {
    if (!view.predicted_px[i]) continue;
    const Eigen::Vector2d& p = *view.predicted_px[i];
    const Eigen::Vector2d r = obs.points_px[i] - p;
    cv::line(*image, Fixed(map(p)), Fixed(map(p + magnification * r)),
             ResidualColor(r.norm(), model.residual_scale_max_px), thick, cv::LINE_AA, kShift);
  }
  // Cross-camera predictions: diamonds around the rings (twice as wide), so
  // they show even when they coincide with the detections.
  for (size_t c = 0; c < view.cross.size(); ++c)
    for (const auto& uv : view.cross[c].predicted_px)
      if (uv) DrawMarker(image, map(*uv), Marker::kDiamond, 2 * ring, kCrossColors[c % 4], 1);
  cv::Mat keep_clear(image->size(), CV_8U, cv::Scalar(0));
  for (const auto& d : obs.points_px)
    cv::circle(keep_clear, Fixed(map(d)), static_cast<int>(std::lround((ring / 2 + 2) * kSubpixel)),
               cv::Scalar(255), cv::FILLED, cv::LINE_8, kShift);
  clean.copyTo(*image, keep_clear);
  for (const auto& d : obs.points_px)
    DrawMarker(image, map(d), Marker::kCircle, ring, kDetected, mark_thick);
  for (const auto& uv : view.predicted_px)
    if (uv) DrawMarker(image, map(*uv), Marker::kCross, 0.5 * ring, kReprojected, mark_thick);
}

// A small target gets an enlarged copy of its region in a free corner, so
// its marks read in the overlay and in the thumbnail. The inset covers no
// point of the view: it is placed clear of the target's region.
void DrawZoomInset(cv::Mat* image, const cv::Mat& clean, const ReportModel& model,
                   const ViewModel& view, double spacing, double magnification, double ui) {
  const Camera& camera = *model.cameras[view.camera].camera;
  Eigen::AlignedBox2d region;
  for (const auto& d : view.observation->points_px) region.extend(d);
  if (view.T_cam_target)
    for (const auto& corner : SheetCorners(*model.dataset->target))
      if (const auto uv = camera.Project(*view.T_cam_target * corner)) region.extend(*uv);
  if (region.isEmpty()) return;
  const cv::Rect whole(0, 0, image->cols, image->rows);
  const double pad = 10 * ui;
  const cv::Rect source =
      cv::Rect(cv::Point(static_cast<int>(std::floor(region.min().x() - pad)),
                         static_cast<int>(std::floor(region.min().y() - pad))),
               cv::Point(static_cast<int>(std::ceil(region.max().x() + pad)) + 1,
                         static_cast<int>(std::ceil(region.max().y() + pad)) + 1)) &
      whole;
  if (source.empty()) return;
  // Up to 4×, in half steps, within 45 % of the width and 62 % of the height.
  const double zoom = std::floor(2 * std::min({4.0, 0.45 * image->cols / source.width,
                                               0.62 * image->rows / source.height})) /
                      2;
  if (zoom < 2) return;
  // Scale factors given (not a size), so resize maps pixels exactly as PixelMap.
  cv::Mat zoomed_clean;
  cv::resize(clean(source), zoomed_clean, cv::Size(), zoom, zoom, cv::INTER_LINEAR);
  const cv::Size size = zoomed_clean.size();
  // Free corners: below the header band, right or left; bottom right (the
  // legend is bottom left). Clear of the target by one point spacing.
  const int margin = static_cast<int>(std::lround(12 * ui));
  const int top = static_cast<int>(std::lround(0.12 * image->rows));
  const cv::Rect keep_out(
      source.x - static_cast<int>(spacing), source.y - static_cast<int>(spacing),
      source.width + 2 * static_cast<int>(spacing), source.height + 2 * static_cast<int>(spacing));
  const cv::Rect candidates[3] = {{image->cols - size.width - margin, top, size.width, size.height},
                                  {image->cols - size.width - margin,
                                   image->rows - size.height - margin, size.width, size.height},
                                  {margin, top, size.width, size.height}};
  for (const cv::Rect& at : candidates) {
    if ((at & whole) != at || (at & keep_out).area() > 0) continue;
    cv::Mat zoomed = zoomed_clean.clone();
    PixelMap map;
    map.origin = Eigen::Vector2d(source.x, source.y);
    map.zoom = zoom;
    DrawMarks(&zoomed, zoomed_clean, model, view, map,
              std::clamp(0.5 * spacing * zoom, 7.0, 18 * ui), magnification, ui);
    zoomed.copyTo((*image)(at));
    cv::rectangle(*image, at, kText, 1);
    cv::rectangle(*image, source, kText, 1);
    char label[64];
    std::snprintf(label, sizeof label, "target region x%g", zoom);
    const double h = 13 * ui;
    Darken(image,
           cv::Rect(at.x, at.y, TextSize(label, h).width + static_cast<int>(12 * ui),
                    static_cast<int>(2 * h)),
           0.3);
    DrawText(image, label, {at.x + 6 * ui, at.y + h}, h, kText, {0, 0.5});
    return;
  }
}

}  // namespace

cv::Mat DrawOverlay(const ReportModel& model, const ViewModel& view, const cv::Mat& gray) {
  const Camera& camera = *model.cameras[view.camera].camera;
  cv::Mat dim;
  if (gray.empty())
    dim = cv::Mat(camera.height, camera.width, CV_8U, cv::Scalar(110));
  else
    gray.convertTo(dim, CV_8U, 0.6, 40);  // less contrast: marks in colour read better
  cv::Mat image;
  cv::cvtColor(dim, image, cv::COLOR_GRAY2BGR);
  if (gray.empty())
    DrawText(&image, "no image in the dataset: marks only", {image.cols / 2.0, image.rows / 2.0},
             std::max(12.0, image.cols / 80.0), {200, 200, 200}, {0.5, 0.5});
  const cv::Mat clean = image.clone();

  // Marks scale with the image so they look alike on 640 and 4000 px images;
  // rings are at most half the point spacing wide, so neighbours stay apart.
  const double ui = std::max(0.55, image.cols / 1920.0);
  const double spacing = PointSpacing(view.observation->points_px);
  const double ring = std::clamp(0.5 * spacing, 7.0, 14 * ui);
  // Residuals magnified so that the colour scale's maximum draws ~50 px long.
  const double magnification = std::max(1.0, NiceFloor(50.0 * ui / model.residual_scale_max_px));
  DrawMarks(&image, clean, model, view, PixelMap{}, ring, magnification, ui);
  if (std::isfinite(spacing)) DrawZoomInset(&image, clean, model, view, spacing, magnification, ui);
  DrawHeader(&image, model, view, ui);
  DrawLegend(&image, model, view, magnification, ui);
  return image;
}

}  // namespace handeye::report
