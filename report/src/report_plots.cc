// SPDX-License-Identifier: GPL-2.0-or-later
// The report's plots, as SVG (report_svg.h): residual histograms and
// image-plane residuals per camera, per-view RMS over the poses, and a
// top-down map of the cell.
#include <algorithm>
#include <cmath>

#include "handeye/core/setup_frames.h"
#include "report_html.h"
#include "report_internal.h"
#include "report_svg.h"

namespace handeye::report {
namespace {

const char* kInk = "#282828";
const char* kBad = "#dc2828";
const char* kGrey = "#5a5a5a";

std::string Histogram(const ReportModel& model, const CameraModel& cam) {
  std::vector<double> residuals;
  for (int v : cam.views)
    if (model.views[v].used)
      for (double r : model.views[v].residual_px)
        if (std::isfinite(r)) residuals.push_back(r);
  // One range for every camera's histogram, so they compare at a glance.
  const double x_max = NiceCeil(std::max(1e-3, 1.15 * model.residual_p99_px));
  constexpr int kBins = 25;
  std::vector<int> counts(kBins, 0);
  int beyond = 0;
  for (double r : residuals) {
    if (r >= x_max)
      ++beyond;
    else
      ++counts[std::min(kBins - 1, static_cast<int>(r / x_max * kBins))];
  }
  const double y_top = NiceCeil(std::max(1, *std::max_element(counts.begin(), counts.end())) * 1.12);
  SvgPlot plot(520, 300, cam.camera->name + ": " + std::to_string(residuals.size()) +
                             " point residuals (used views)");
  plot.x = {0, x_max, "reprojection error (px)"};
  plot.y = {0, y_top, "points"};
  plot.Frame();
  Svg& svg = plot.svg;
  for (int b = 0; b < kBins; ++b) {
    const cv::Scalar fill = ResidualColor(x_max * (b + 0.5) / kBins, model.residual_scale_max_px);
    if (counts[b] > 0)
      svg.Rect(plot.At(x_max * b / kBins, 0), plot.At(x_max * (b + 1) / kBins, counts[b]),
               Hex(fill), Hex(0.7 * fill));
  }
  if (residuals.empty()) {
    svg.Text(plot.At(x_max / 2, y_top / 2), "no used views", 14, kInk, "middle");
    return plot.str();
  }
  const double rms = cam.result->rms_px;
  svg.Line({plot.At(rms, 0), plot.At(rms, y_top)}, kInk, 1, {{"stroke-dasharray", "4 4"}});
  // An RMS that is not finite has no line; its label goes to the left.
  svg.Text(plot.At(std::isfinite(rms) ? rms : 0, y_top) + Svg::P(5, 12),
           "RMS " + Num(rms, 3) + " px", 11, kInk);
  if (beyond > 0)
    svg.Text(plot.At(x_max, y_top) + Svg::P(-6, 30),
             std::to_string(beyond) + " beyond " + TickLabel(x_max, x_max) + " px", 11, kBad,
             "end");
  return plot.str();
}

std::string ImagePlane(const ReportModel& model, const CameraModel& cam) {
  const Camera& camera = *cam.camera;
  const double width = 560, right = 96, area_w = width - 72 - right;
  SvgPlot plot(width, area_w * camera.height / std::max(1, camera.width) + 36 + 50,
               camera.name + ": residuals in the image", right);
  plot.x = {-0.5, camera.width - 0.5, "u (px)"};
  plot.y = {-0.5, camera.height - 0.5, "v (px)"};
  plot.y_down = true;
  plot.EqualAspect();
  // Vectors magnified so the 99th-percentile residual draws ~14 px: long
  // enough to show a pattern, short enough not to cover the others.
  const double magnification =
      std::max(1.0, NiceFloor(14.0 / (std::max(1e-3, model.residual_p99_px) * plot.PxPerUnitX())));
  plot.title = camera.name + ": residuals in the image (vectors ×" +
               TickLabel(magnification, magnification) + ")";
  plot.Frame(false);
  Svg& svg = plot.svg;
  const double u1 = camera.width - 0.5, v1 = camera.height - 0.5;
  svg.Line({plot.At(-0.5, -0.5), plot.At(u1, -0.5), plot.At(u1, v1), plot.At(-0.5, v1),
            plot.At(-0.5, -0.5)},
           "#a0a0a0");  // the sensor's outline
  for (int v : cam.views) {
    const ViewModel& view = model.views[v];
    if (!view.used) continue;
    for (size_t i = 0; i < view.predicted_px.size(); ++i) {
      if (!view.predicted_px[i]) continue;
      const Eigen::Vector2d& d = view.observation->points_px[i];
      const Eigen::Vector2d r = d - *view.predicted_px[i];
      const std::string colour = Hex(ResidualColor(r.norm(), model.residual_scale_max_px));
      svg.Line({plot.At(d), plot.At(d + magnification * r)}, colour);
      svg.Mark(plot.At(d), Shape::kDisc, 3, colour);
    }
  }
  plot.ColorBar(0, model.residual_scale_max_px, "reprojection error (px)",
                [&](double v) { return ResidualColor(v, model.residual_scale_max_px); });
  return plot.str();
}

std::string ViewRms(const ReportModel& model) {
  double y_max = 0;
  for (const ViewModel& v : model.views)
    if (v.used && !v.outlier && v.T_cam_target && std::isfinite(v.rms_px))
      y_max = std::max(y_max, v.rms_px);
  y_max = NiceCeil(std::max(y_max * 1.2, 0.1));
  std::vector<SvgPlot::LegendEntry> legend;
  for (size_t k = 0; k < model.cameras.size(); ++k)
    legend.push_back({model.cameras[k].camera->name, Hex(CameraColor(int(k))), Shape::kDisc});
  legend.push_back({"outlier (down-weighted)", kBad, Shape::kRing});
  legend.push_back({"rejected view (at 0)", kGrey, Shape::kCross});
  // Views above the range are drawn at its top, marked and labelled.
  SvgPlot plot(1000, 340, "RMS reprojection error per view", SvgPlot::LegendWidth(legend) + 24);
  plot.x = {0.5, std::max<double>(model.dataset->poses.size(), 2) + 0.5, "pose (dataset order)"};
  plot.y = {0, y_max, "view RMS (px)"};
  plot.Frame();
  Svg& svg = plot.svg;
  for (size_t k = 0; k < model.cameras.size(); ++k) {
    const std::string colour = Hex(CameraColor(int(k)));
    std::vector<const ViewModel*> used;
    for (int v : model.cameras[k].views) {
      const ViewModel& view = model.views[v];
      if (view.T_cam_target && view.used)
        used.push_back(&view);
      else if (view.T_cam_target)
        svg.Mark(plot.At(view.pose + 1, 0), Shape::kCross, 9, colour, 2);
    }
    std::sort(used.begin(), used.end(), [](auto* a, auto* b) { return a->pose < b->pose; });
    std::vector<Svg::P> line;
    for (const ViewModel* view : used)
      line.push_back(plot.At(view->pose + 1, std::min(view->rms_px, y_max)));
    svg.Line(line, colour);
    for (size_t i = 0; i < used.size(); ++i) {
      const Svg::P& p = line[i];
      if (used[i]->rms_px > y_max) {
        svg.Mark(p, Shape::kTriangle, 10, kBad);
        svg.Text(p + Svg::P(7, 6), Num(used[i]->rms_px, 1), 10, kBad);
      } else {
        svg.Mark(p, Shape::kDisc, 6, colour);
      }
      if (used[i]->outlier) svg.Mark(p, Shape::kRing, 14, kBad, 2);
    }
  }
  plot.Legend(legend);
  return plot.str();
}

// Top-down map in the base frame (z up): x right, y up.
std::string Map(const ReportModel& model) {
  const Dataset& dataset = *model.dataset;
  const CalibrationResult& result = *model.result;
  const SetupFrames frames = FramesOf(dataset.setup);
  // Cameras on the base stand still in this map; on the flange they move with the robot.
  const bool cameras_on_base = frames.mount == "base";
  const Eigen::Vector2d centre2 = dataset.target->Extent().center();
  const Eigen::Vector3d target_centre(centre2.x(), centre2.y(), 0);

  struct Sighting {
    int camera;
    Eigen::Vector3d camera_at, target_at, view_dir;  // base frame
  };
  std::vector<Sighting> sightings;
  Eigen::Vector2d lo = Eigen::Vector2d::Zero(), hi = lo;  // the base is always in view
  for (const ViewModel& view : model.views) {
    const CameraModel& cam = model.cameras[view.camera];
    if (!cam.result->calibrated || !view.used) continue;
    const Eigen::Isometry3d& T_base_ee = dataset.poses[view.pose].T_base_ee;
    const Eigen::Isometry3d Z = cam.result->own_T_target.value_or(result.T_target);
    // T_cam is T_mount_cam and Z T_holder_target; one of mount and holder is the base.
    const Eigen::Isometry3d T_base_target = frames.BaseFromHolder(T_base_ee) * Z;
    const Eigen::Isometry3d T_base_cam = frames.BaseFromMount(T_base_ee) * cam.result->T_cam;
    const Sighting s{view.camera, T_base_cam.translation(), T_base_target * target_centre,
                     T_base_cam.rotation().col(2)};
    if (!s.camera_at.allFinite() || !s.target_at.allFinite()) continue;
    sightings.push_back(s);
    for (const Eigen::Vector3d& p : {s.camera_at, s.target_at}) {
      lo = lo.cwiseMin(p.head<2>());
      hi = hi.cwiseMax(p.head<2>());
    }
  }
  const double span = std::max(0.5, (hi - lo).maxCoeff());
  // Room around the outermost items for markers and arrows.
  lo -= Eigen::Vector2d::Constant(0.12 * span);
  hi += Eigen::Vector2d::Constant(0.12 * span);
  std::vector<SvgPlot::LegendEntry> legend;
  for (size_t k = 0; k < model.cameras.size(); ++k)
    legend.push_back({model.cameras[k].camera->name, Hex(CameraColor(int(k))), Shape::kTriangle});
  legend.push_back({cameras_on_base ? "target, as seen by camera" : "target centre", kGrey});
  legend.push_back(
      {cameras_on_base ? "camera, arrow: view axis" : "camera at a pose, view axis", kGrey,
       Shape::kTriangle});
  legend.push_back({"robot base, x and y axes", "#1e1e1e", Shape::kSquare});
  const double legend_w = SvgPlot::LegendWidth(legend) + 24;
  SvgPlot plot(640 + legend_w, 640, "Cell from above (base frame, z up)", legend_w);
  plot.x = {lo.x(), hi.x(), "x_base (m)"};
  plot.y = {lo.y(), hi.y(), "y_base (m)"};
  plot.EqualAspect();
  plot.Frame();
  Svg& svg = plot.svg;
  // Sight lines, faint, so the eye sees which camera saw which target pose.
  for (const Sighting& s : sightings)
    svg.Line({plot.At(s.camera_at.head<2>()), plot.At(s.target_at.head<2>())},
             Hex(CameraColor(s.camera)), 1, {{"stroke-opacity", 0.25}});
  const double arrow = 0.12 * span;
  svg.Arrow(plot.At(0, 0), plot.At(arrow, 0), "#dc2828", 2, 8);
  svg.Arrow(plot.At(0, 0), plot.At(0, arrow), "#28a028", 2, 8);
  svg.Mark(plot.At(0, 0), Shape::kSquare, 14, "#1e1e1e");
  svg.Text(plot.At(0, 0) + Svg::P(10, 16), "robot base", 11, "#1e1e1e");
  if (!cameras_on_base) {
    const Svg::P t = plot.At((result.T_target * target_centre).head<2>());
    svg.Mark(t, Shape::kDiamond, 16, "#1e1e1e", 2);
    svg.Text(t + Svg::P(12, -4), "target (fixed)", 11, "#1e1e1e");
  }
  for (const Sighting& s : sightings)
    svg.Mark(plot.At(s.target_at.head<2>()), Shape::kDisc, 5, Hex(CameraColor(s.camera)));
  for (size_t k = 0; k < model.cameras.size(); ++k) {
    const CameraModel& cam = model.cameras[k];
    const std::string colour = Hex(CameraColor(int(k)));
    if (!cam.result->calibrated) continue;
    if (!cameras_on_base) {
      for (const Sighting& s : sightings)
        if (s.camera == int(k)) {
          const Eigen::Vector2d at = s.camera_at.head<2>();
          svg.Arrow(plot.At(at), plot.At(at + 0.5 * arrow * s.view_dir.head<2>()), colour, 1, 6);
          svg.Mark(plot.At(at), Shape::kTriangle, 9, colour);
        }
      continue;
    }
    const Eigen::Vector3d at = cam.result->T_cam.translation(),
                          dir = cam.result->T_cam.rotation().col(2);
    // The optical axis seen from above: short when the camera looks down,
    // so the label gives its angle to the horizontal too.
    svg.Arrow(plot.At(at.head<2>()), plot.At(at.head<2>() + arrow * dir.head<2>()), colour, 2, 9);
    svg.Mark(plot.At(at.head<2>()), Shape::kTriangle, 15, colour);
    const double tilt_deg = std::asin(std::clamp(dir.z(), -1.0, 1.0)) * 180.0 / M_PI;
    // Labels point inwards, so they stay inside the frame.
    const bool right_half = at.x() > 0.5 * (lo.x() + hi.x());
    svg.Text(plot.At(at.head<2>()) + Svg::P(right_half ? -12 : 12, -12),
             cam.camera->name + " (z " + Num(at.z(), 2) + " m, looks " +
                 Num(std::abs(tilt_deg), 0) + "° " + (tilt_deg <= 0 ? "down" : "up") + ")",
             11, colour, right_half ? "end" : "start");
  }
  plot.Legend(legend);
  return plot.str();
}

}  // namespace

Plots DrawPlots(const ReportModel& model) {
  Plots plots;
  for (const CameraModel& cam : model.cameras) {
    plots.histograms.push_back(Histogram(model, cam));
    plots.image_plane.push_back(ImagePlane(model, cam));
  }
  plots.view_rms = ViewRms(model);
  plots.map = Map(model);
  return plots;
}

}  // namespace handeye::report
