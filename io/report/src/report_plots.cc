// SPDX-License-Identifier: GPL-2.0-or-later
// The report's plots, drawn with report_plot.h: residual histograms and
// image-plane residuals per camera, per-view RMS over the poses, and a
// top-down map of the cell.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "handeye/core/setup_frames.h"
#include "handeye/io/image.h"
#include "report_internal.h"
#include "report_plot.h"

namespace handeye::report {
namespace {

const cv::Scalar kInk(40, 40, 40);
const cv::Scalar kBad(40, 40, 220);

std::string Format(const char* format, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, value);
  return buf;
}

double NiceCeil(double value) {
  if (!(value > 0)) return 1.0;
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * decade >= value * (1 - 1e-12)) return m * decade;
  return 10 * decade;
}

double NiceFloor(double value) {
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * decade <= value * (1 + 1e-12)) return m * decade;
  return decade;
}

cv::Mat Histogram(const ReportModel& model, const CameraModel& cam) {
  std::vector<double> residuals;
  for (int v : cam.views)
    if (model.views[v].used)
      residuals.insert(residuals.end(), model.views[v].residual_px.begin(),
                       model.views[v].residual_px.end());
  // One range for every camera's histogram, so they compare at a glance.
  const double x_max = NiceCeil(std::max(1e-3, 1.15 * model.residual_p99_px));
  constexpr int kBins = 25;
  std::vector<int> counts(kBins, 0);
  int beyond = 0;
  for (double r : residuals) {
    if (r >= x_max) {
      ++beyond;
      continue;
    }
    ++counts[std::min(kBins - 1, static_cast<int>(r / x_max * kBins))];
  }
  const int top = std::max(1, *std::max_element(counts.begin(), counts.end()));
  Plot plot(
      520, 300,
      cam.camera->name + ": " + std::to_string(residuals.size()) + " point residuals (used views)");
  plot.SetX(0, x_max, "reprojection error (px)");
  plot.SetY(0, NiceCeil(top * 1.12), "points");
  plot.DrawFrame();
  for (int b = 0; b < kBins; ++b)
    if (counts[b] > 0)
      plot.Bar(x_max * b / kBins, x_max * (b + 1) / kBins, counts[b],
               ResidualColor(x_max * (b + 0.5) / kBins, model.residual_scale_max_px));
  if (!residuals.empty()) {
    const double y_top = NiceCeil(top * 1.12);
    const double rms = cam.result->rms_px;
    plot.DashedLine({rms, 0}, {rms, y_top}, kInk);
    plot.Label({rms, y_top}, "RMS " + Format("%.3f", rms) + " px", kInk, 5, 6, {0, 0}, 11);
    if (beyond > 0)
      plot.Label({x_max, y_top}, std::to_string(beyond) + " beyond " + Format("%g", x_max) + " px",
                 kBad, -6, 24, {1, 0}, 11);
  } else {
    plot.Label({x_max / 2, 0.5}, "no used views", kInk, 0, 0, {0.5, 0.5}, 14);
  }
  return plot.image();
}

cv::Mat ImagePlane(const ReportModel& model, const CameraModel& cam) {
  const Camera& camera = *cam.camera;
  const int width = 560;
  const int area_w = width - 78 - 90;
  const int height = static_cast<int>(area_w * double(camera.height) / camera.width) + 38 + 52;
  Plot plot(width, height, "title", 90);
  plot.SetX(-0.5, camera.width - 0.5, "u (px)");
  plot.SetY(-0.5, camera.height - 0.5, "v (px)", true);
  plot.EqualAspect();
  // Vectors magnified so the 99th-percentile residual draws ~14 plot pixels:
  // long enough to show a pattern, short enough not to cover the others.
  const double magnification =
      std::max(1.0, NiceFloor(14.0 / (std::max(1e-3, model.residual_p99_px) * plot.PxPerUnitX())));
  plot.SetTitle(cam.camera->name + ": residuals in the image (vectors x" +
                TickLabel(magnification, magnification) + ")");
  plot.DrawFrame(false);
  // The sensor's outline, then the points on it.
  plot.Line({{-0.5, -0.5},
             {camera.width - 0.5, -0.5},
             {camera.width - 0.5, camera.height - 0.5},
             {-0.5, camera.height - 0.5},
             {-0.5, -0.5}},
            {160, 160, 160}, 1);
  for (int v : cam.views) {
    const ViewModel& view = model.views[v];
    if (!view.used) continue;
    for (size_t i = 0; i < view.predicted_px.size(); ++i) {
      if (!view.predicted_px[i]) continue;
      const Eigen::Vector2d& d = view.observation->points_px[i];
      const Eigen::Vector2d r = d - *view.predicted_px[i];
      const cv::Scalar color = ResidualColor(r.norm(), model.residual_scale_max_px);
      plot.Line({d, d + magnification * r}, color, 1);
      plot.Point(d, Marker::kDisc, 3, color);
    }
  }
  plot.ColorBar(0, model.residual_scale_max_px, "reprojection error (px)",
                [&](double v) { return ResidualColor(v, model.residual_scale_max_px); });
  return plot.image();
}

cv::Mat ViewRms(const ReportModel& model) {
  const int poses = static_cast<int>(model.dataset->poses.size());
  double y_max = 0;
  for (const ViewModel& v : model.views)
    if (v.used && !v.outlier && v.T_cam_target) y_max = std::max(y_max, v.rms_px);
  y_max = NiceCeil(std::max(y_max * 1.2, 0.1));
  std::vector<LegendEntry> legend;
  for (size_t k = 0; k < model.cameras.size(); ++k)
    legend.push_back(
        {model.cameras[k].camera->name, CameraColor(static_cast<int>(k)), Marker::kDisc});
  legend.push_back({"outlier (down-weighted)", kBad, Marker::kCircle});
  legend.push_back({"rejected view (at 0)", {90, 90, 90}, Marker::kCross});
  // Outliers above the range are clipped to its top and labelled.
  Plot plot(1000, 340, "RMS reprojection error per view", Plot::LegendWidth(legend) + 24);
  plot.SetX(0.5, std::max(poses, 2) + 0.5, "pose (dataset order)");
  plot.SetY(0, y_max, "view RMS (px)");
  plot.DrawFrame();
  for (size_t k = 0; k < model.cameras.size(); ++k) {
    const CameraModel& cam = model.cameras[k];
    const cv::Scalar color = CameraColor(static_cast<int>(k));
    std::vector<Eigen::Vector2d> line;
    for (int v : cam.views) {
      const ViewModel& view = model.views[v];
      if (!view.T_cam_target) continue;
      const Eigen::Vector2d p(view.pose + 1, std::min(view.rms_px, y_max));
      if (!view.used) {
        plot.Point({view.pose + 1.0, 0.0}, Marker::kCross, 9, color, 2);
        continue;
      }
      line.push_back(p);
    }
    std::sort(line.begin(), line.end(), [](const auto& a, const auto& b) { return a.x() < b.x(); });
    plot.Line(line, color, 1);
    for (int v : cam.views) {
      const ViewModel& view = model.views[v];
      if (!view.T_cam_target || !view.used) continue;
      const Eigen::Vector2d p(view.pose + 1, std::min(view.rms_px, y_max));
      if (view.rms_px > y_max) {
        plot.Point(p, Marker::kTriangle, 10, kBad);
        plot.Label(p, Format("%.1f", view.rms_px), kBad, 7, 2, {0, 0}, 10);
      } else {
        plot.Point(p, Marker::kDisc, 6, color);
      }
      if (view.outlier) plot.Point(p, Marker::kCircle, 14, kBad, 2);
    }
  }
  plot.Legend(legend, Plot::Place::kMargin);
  return plot.image();
}

// Top-down map in the base frame (z up): x right, y up.
cv::Mat Map(const ReportModel& model) {
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
  std::vector<Eigen::Vector3d> extent_points = {Eigen::Vector3d::Zero()};
  for (const ViewModel& view : model.views) {
    const CameraModel& cam = model.cameras[view.camera];
    if (!cam.result->calibrated || !view.used) continue;
    const Eigen::Isometry3d& T_base_ee = dataset.poses[view.pose].T_base_ee;
    const Eigen::Isometry3d Z = cam.result->own_T_target.value_or(result.T_target);
    // T_cam is T_mount_cam and Z T_holder_target; one of mount and holder is the base.
    const Eigen::Isometry3d T_base_target = frames.BaseFromHolder(T_base_ee) * Z;
    const Eigen::Isometry3d T_base_cam = frames.BaseFromMount(T_base_ee) * cam.result->T_cam;
    sightings.push_back({view.camera, T_base_cam.translation(), T_base_target * target_centre,
                         T_base_cam.rotation().col(2)});
    extent_points.push_back(sightings.back().camera_at);
    extent_points.push_back(sightings.back().target_at);
  }
  Eigen::Vector2d lo = extent_points[0].head<2>(), hi = lo;
  for (const auto& p : extent_points) {
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  const double span = std::max(0.5, (hi - lo).maxCoeff());
  // Room around the outermost items for markers and arrows.
  lo -= Eigen::Vector2d::Constant(0.12 * span);
  hi += Eigen::Vector2d::Constant(0.12 * span);
  std::vector<LegendEntry> legend;
  for (size_t k = 0; k < model.cameras.size(); ++k)
    legend.push_back(
        {model.cameras[k].camera->name, CameraColor(static_cast<int>(k)), Marker::kTriangle});
  legend.push_back(
      {cameras_on_base ? "target, as seen by camera" : "target centre", {90, 90, 90}, Marker::kDisc});
  legend.push_back({cameras_on_base ? "camera, arrow: view axis" : "camera at a pose, view axis",
                    {90, 90, 90},
                    Marker::kTriangle});
  legend.push_back({"robot base, x and y axes", {30, 30, 30}, Marker::kSquare});
  const int legend_w = Plot::LegendWidth(legend) + 24;
  Plot plot(640 + legend_w, 640, std::string("Cell from above (base frame, z up)"), legend_w);
  plot.SetX(lo.x(), hi.x(), "x_base (m)");
  plot.SetY(lo.y(), hi.y(), "y_base (m)");
  plot.EqualAspect();
  plot.DrawFrame();

  // Sight lines, faint, so the eye sees which camera saw which target pose.
  cv::Mat layer = plot.image().clone();
  {
    cv::Mat area = layer(plot.area());
    for (const Sighting& s : sightings) {
      cv::Point2d a = plot.Px(s.camera_at.x(), s.camera_at.y()),
                  b = plot.Px(s.target_at.x(), s.target_at.y());
      a -= cv::Point2d(plot.area().x, plot.area().y);
      b -= cv::Point2d(plot.area().x, plot.area().y);
      cv::line(area, Fixed(a), Fixed(b), CameraColor(s.camera), 1, cv::LINE_AA, kShift);
    }
  }
  cv::addWeighted(plot.image(), 0.75, layer, 0.25, 0, plot.image());

  const double arrow = 0.12 * span;
  // Robot base and its axes.
  plot.Arrow({0, 0}, {arrow, 0}, {40, 40, 220}, 2, 8);
  plot.Arrow({0, 0}, {0, arrow}, {40, 160, 40}, 2, 8);
  plot.Point({0, 0}, Marker::kSquare, 14, {30, 30, 30});
  plot.Label({0, 0}, "robot base", {30, 30, 30}, 10, 12, {0, 0}, 11);
  if (!cameras_on_base) {
    const Eigen::Vector3d t = result.T_target * target_centre;
    plot.Point(t.head<2>(), Marker::kDiamond, 16, {30, 30, 30}, 2);
    plot.Label(t.head<2>(), "target (fixed)", {30, 30, 30}, 12, -4, {0, 0.5}, 11);
  }
  for (const Sighting& s : sightings)
    plot.Point(s.target_at.head<2>(), Marker::kDisc, 5, CameraColor(s.camera));
  for (size_t k = 0; k < model.cameras.size(); ++k) {
    const CameraModel& cam = model.cameras[k];
    const cv::Scalar color = CameraColor(static_cast<int>(k));
    if (!cam.result->calibrated) continue;
    if (cameras_on_base) {
      const Eigen::Isometry3d& T = cam.result->T_cam;
      const Eigen::Vector3d at = T.translation(), dir = T.rotation().col(2);
      // The optical axis seen from above: short when the camera looks down.
      plot.Arrow(at.head<2>(), at.head<2>() + arrow * dir.head<2>(), color, 2, 9);
      plot.Point(at.head<2>(), Marker::kTriangle, 15, color);
      // Labels point inwards, so they stay inside the frame.
      const bool right_half = at.x() > 0.5 * (lo.x() + hi.x());
      plot.Label(at.head<2>(), cam.camera->name + " (z " + Format("%.2f", at.z()) + " m)", color,
                 right_half ? -12 : 12, -12, {right_half ? 1.0 : 0.0, 0.5}, 11);
    } else {
      for (const Sighting& s : sightings) {
        if (s.camera != static_cast<int>(k)) continue;
        plot.Arrow(s.camera_at.head<2>(),
                   s.camera_at.head<2>() + 0.5 * arrow * s.view_dir.head<2>(), color, 1, 6);
        plot.Point(s.camera_at.head<2>(), Marker::kTriangle, 9, color);
      }
    }
  }
  plot.Legend(legend, Plot::Place::kMargin);
  return plot.image();
}

}  // namespace

PlotFiles WritePlots(const ReportModel& model, const std::string& dir) {
  std::filesystem::create_directories(std::filesystem::path(dir) / "plots");
  PlotFiles files;
  for (size_t k = 0; k < model.cameras.size(); ++k) {
    const CameraModel& cam = model.cameras[k];
    files.histograms.push_back("plots/histogram_" + cam.folder + ".png");
    WritePng(dir + "/" + files.histograms.back(), Histogram(model, cam));
    files.image_plane.push_back("plots/image_plane_" + cam.folder + ".png");
    WritePng(dir + "/" + files.image_plane.back(), ImagePlane(model, cam));
  }
  files.view_rms = "plots/view_rms.png";
  WritePng(dir + "/" + files.view_rms, ViewRms(model));
  files.map = "plots/map.png";
  WritePng(dir + "/" + files.map, Map(model));
  return files;
}

}  // namespace handeye::report
