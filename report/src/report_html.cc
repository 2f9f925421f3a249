// SPDX-License-Identifier: GPL-2.0-or-later
// The report's index.html: one self-contained page (inline CSS and SVG
// plots, relative image links, no JavaScript, no network) that opens from disk.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "handeye/core/transform.h"
#include "handeye/core/setup_frames.h"
#include "report_html.h"
#include "report_internal.h"

namespace handeye::report {

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string Num(double value, int decimals) {
  if (!std::isfinite(value)) return "n/a";
  // to_chars, unlike printf, ignores the locale: always a decimal point.
  char buf[400];
  const auto end = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::fixed,
                                 std::clamp(decimals, 0, 17));
  std::string s(buf, end.ec == std::errc() ? end.ptr : buf);
  if (s.find_first_not_of("-0.") == std::string::npos && s[0] == '-') s.erase(0, 1);  // no "-0.00"
  return s;
}

std::string TickLabel(double value, double step) {
  int decimals = 0;
  for (double scaled = step; decimals < 6 && std::abs(scaled - std::round(scaled)) > 1e-6 * scaled;
       scaled *= 10)
    ++decimals;
  return Num(value, decimals);
}

std::string Triple(const Eigen::Vector3d& v, int decimals) {
  return Num(v.x(), decimals) + ", " + Num(v.y(), decimals) + ", " + Num(v.z(), decimals);
}

std::string Quaternion(const Eigen::Matrix3d& R) {
  Eigen::Quaterniond q(R);
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return Num(q.x(), 5) + ", " + Num(q.y(), 5) + ", " + Num(q.z(), 5) + ", " + Num(q.w(), 5);
}

std::string Swatch(int camera) {
  const cv::Scalar c = CameraColor(camera);  // BGR
  char buf[96];
  std::snprintf(buf, sizeof buf,
                "<span class=\"swatch\" style=\"background: rgb(%d,%d,%d)\"></span>", int(c[2]),
                int(c[1]), int(c[0]));
  return buf;
}

namespace {

const char* kStyle = R"(
body { font-family: "DejaVu Sans", "Helvetica Neue", Arial, sans-serif; margin: 24px 32px; color: #222;
       background: #fafafa; font-size: 14px; line-height: 1.45; }
h1 { font-size: 24px; margin: 0 0 4px 0; }
h2 { font-size: 19px; margin: 28px 0 8px 0; border-bottom: 2px solid #ddd; padding-bottom: 3px; }
h3 { font-size: 15px; margin: 18px 0 6px 0; }
.meta { color: #555; margin: 2px 0; }
.verdict { margin: 12px 0; padding: 10px 14px; border-radius: 4px; font-size: 15px; }
.verdict.ok { background: #e6f4e6; border-left: 6px solid #3a9a3a; }
.verdict.warn { background: #fff4e0; border-left: 6px solid #e08a00; }
.warnings { background: #fff4e0; border: 1px solid #f0c27a; border-radius: 4px; padding: 8px 12px 8px 30px; }
.warnings li { margin: 3px 0; }
.notes { color: #555; }
table { border-collapse: collapse; background: white; margin: 6px 0; }
th, td { border: 1px solid #d8d8d8; padding: 4px 8px; text-align: right; white-space: nowrap; }
td { font-variant-numeric: tabular-nums; }
th { background: #eef0f3; font-weight: 600; }
td.name, th.name { text-align: left; }
tr.flag td { background: #fff4e0; }
.swatch { display: inline-block; width: 10px; height: 10px; border-radius: 2px; margin-right: 6px; }
.plots svg, .grid img { border: 1px solid #ddd; background: white; }
.plots { display: flex; flex-wrap: wrap; gap: 10px; align-items: flex-start; }
.grid { display: flex; flex-wrap: wrap; gap: 10px; }
figure { margin: 0; background: white; border: 1px solid #e2e2e2; padding: 4px; }
figure.outlier { border: 2px solid #d33; }
figure.rejected { border: 2px solid #e08a00; }
figcaption { font-size: 12px; color: #333; max-width: 320px; }
.bad { color: #c22; font-weight: 600; }
.small { font-size: 12px; color: #555; }
)";

std::string Figure(const ReportModel& model, const ViewModel& view, int thumb_w) {
  const Camera& camera = *model.cameras[view.camera].camera;
  const int thumb_h = static_cast<int>(std::lround(double(thumb_w) * camera.height / camera.width));
  std::ostringstream out;
  const char* cls = !view.used ? " class=\"rejected\"" : view.outlier ? " class=\"outlier\"" : "";
  out << "<figure" << cls << "><a href=\"" << view.overlay_path << "\"><img src=\""
      << view.thumb_path << "\" width=\"" << thumb_w << "\" height=\"" << thumb_h << "\" alt=\""
      << Escape(camera.name) << " pose " << Escape(view.observation->pose_id)
      << "\"></a><figcaption>" << Swatch(view.camera) << Escape(camera.name) << " · pose "
      << Escape(view.observation->pose_id) << " · ";
  if (view.T_cam_target)
    out << "RMS " << Num(view.rms_px, 3) << " px, max " << Num(view.max_px, 3) << " px";
  else
    out << "not calibrated";
  if (view.outlier) out << " · <span class=\"bad\">outlier</span>";
  if (!view.used)
    out << " · <span class=\"bad\">rejected</span>: " << Escape(view.rejected_because);
  out << "</figcaption></figure>\n";
  return out.str();
}

// 1σ of a point 1 m and 3 m in front of the camera, in the parent frame (mm):
// the camera's position and orientation uncertainty where a user places things.
}  // namespace

std::string RenderHtml(const ReportModel& model, const Plots& plots,
                       const ReportOptions& options) {
  const Dataset& dataset = *model.dataset;
  const CalibrationResult& result = *model.result;
  std::ostringstream out;
  out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      << "<title>Hand-eye calibration report</title>\n<style>" << kStyle
      << "</style>\n</head>\n<body>\n";

  out << "<h1>Hand-eye calibration report</h1>\n<p class=\"meta\">setup <b>"
      << SetupName(dataset.setup) << "</b> · method <b>" << MethodName(result.method) << "</b> · "
      << dataset.cameras.size() << " cameras · " << dataset.poses.size() << " robot poses · "
      << model.views.size() << " views · target " << Escape(dataset.target->Type()) << "</p>\n";
  if (!options.dataset_label.empty())
    out << "<p class=\"meta\">dataset: <code>" << Escape(options.dataset_label) << "</code></p>\n";
  if (!options.result_label.empty())
    out << "<p class=\"meta\">result: <code>" << Escape(options.result_label) << "</code></p>\n";
  out << "<div class=\"verdict " << (model.warnings.empty() ? "ok" : "warn") << "\">RMS <b>"
      << Num(result.metrics.rms_px, 3) << " px</b> over all used views · AX=ZB <b>"
      << Num(result.metrics.axzb_camera_translation_mm, 2) << " mm</b> (cameras in the "
      << FramesOf(result.setup).mount << " frame) / <b>"
      << Num(result.metrics.axzb_rotation_deg, 3) << "°</b> · solver "
      << (result.solver.converged ? "converged" : "<span class=\"bad\">did not converge</span>")
      << " (" << result.solver.iterations << " iterations, " << Num(result.solver.seconds, 2)
      << " s) · ";
  if (model.warnings.empty())
    out << "<b>no warnings</b>";
  else
    out << "<b>" << model.warnings.size() << (model.warnings.size() == 1 ? " warning" : " warnings")
        << "</b>";
  out << "</div>\n";

  if (!model.warnings.empty()) {
    out << "<h2 id=\"warnings\">Warnings</h2>\n<ul class=\"warnings\">\n";
    for (const Warning& w : model.warnings) out << "<li>" << Escape(w.text) << "</li>\n";
    out << "</ul>\n";
  }

  out << "<h2 id=\"cameras\">Cameras</h2>\n";
  CameraTables(model, out);
  UncertaintyTable(model, out);
  IntrinsicsTable(model, out);
  SharedAndPairs(model, out);
  NextCaptureSection(model.next, out);

  out << "<h2 id=\"plots\">Plots</h2>\n<div class=\"plots\">\n"
      << plots.map << plots.view_rms << "</div>\n<h3>Residual histograms</h3>\n<div class=\"plots\">\n";
  for (const std::string& svg : plots.histograms) out << svg;
  out << "</div>\n<h3>Residuals in the image plane</h3>\n<div class=\"plots\">\n";
  for (const std::string& svg : plots.image_plane) out << svg;
  out << "</div>\n";

  // Worst views first: they are where a problem shows.
  std::vector<int> order;
  for (size_t i = 0; i < model.views.size(); ++i)
    if (model.views[i].T_cam_target) order.push_back(static_cast<int>(i));
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return model.views[a].rms_px > model.views[b].rms_px; });
  if (order.size() > 10) order.resize(10);
  out << "<h2 id=\"worst\">Worst " << order.size()
      << " views</h2>\n<p class=\"small\">By RMS through the calibrated "
      << "chain. Click a thumbnail for the full-resolution overlay.</p>\n<div class=\"grid\">\n";
  for (int i : order) out << Figure(model, model.views[i], options.thumbnail_width_px);
  out << "</div>\n";

  out << "<h2 id=\"views\">All views</h2>\n";
  for (const CameraModel& cam : model.cameras) {
    out << "<h3>" << Escape(cam.camera->name) << " (" << cam.views.size()
        << " views)</h3>\n<div class=\"grid\">\n";
    for (int v : cam.views) out << Figure(model, model.views[v], options.thumbnail_width_px);
    out << "</div>\n";
  }

  out << "<h2 id=\"legend\">Reading the overlays</h2>\n<ul>\n"
      << "<li>Cyan rings: target points the detector found.</li>\n"
      << "<li>Magenta crosses: the same points projected through the calibrated chain (robot pose, "
         "calibrated camera "
         "and target transforms, lens model).</li>\n"
      << "<li>Coloured lines from each cross: the residual (detected − reprojected), magnified by "
         "the factor in the "
         "overlay's legend; green is small, red is at or above "
      << Num(model.residual_scale_max_px, 2)
      << " px (the same scale in every overlay and plot).</li>\n"
      << "<li>Diamonds: where another camera that saw the target at the same pose predicts the "
         "points, through the "
         "camera-pair transform T_camk_camt.</li>\n"
      << "<li>Blue outline and x (red), y (green), z (blue) axes: the target sheet at its "
         "calibrated pose.</li>\n"
      << "<li>A red frame marks a view the solver down-weighted as an outlier; an orange frame a "
         "view rejected "
         "before the solve.</li>\n</ul>\n";
  if (!model.notes.empty() || !result.notes.empty()) {
    out << "<h2 id=\"notes\">Notes</h2>\n<ul class=\"notes\">\n";
    for (const auto& n : result.notes) out << "<li>calibration: " << Escape(n) << "</li>\n";
    for (const auto& n : model.notes) out << "<li>" << Escape(n) << "</li>\n";
    out << "</ul>\n";
  }
  out << "<p class=\"small\">Written by <code>handeye report</code>. Solver termination: "
      << Escape(result.solver.termination) << ".</p>\n</body>\n</html>\n";
  return out.str();
}

}  // namespace handeye::report
