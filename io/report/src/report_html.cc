// SPDX-License-Identifier: GPL-2.0-or-later
// The report's index.html: one self-contained page (inline CSS, relative
// image links, no JavaScript, no network) that opens from disk.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "handeye/core/transform.h"
#include "report_internal.h"

namespace handeye::report {
namespace {

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
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  std::string s = buf;
  if (s.find_first_not_of("-0.") == std::string::npos && s[0] == '-') s.erase(0, 1);  // no "-0.00"
  return s;
}

std::string Triple(const Eigen::Vector3d& v, int decimals) {
  return Num(v.x(), decimals) + ", " + Num(v.y(), decimals) + ", " + Num(v.z(), decimals);
}

std::string Quaternion(const Eigen::Matrix3d& R) {
  Eigen::Quaterniond q(R);
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return Num(q.x(), 5) + ", " + Num(q.y(), 5) + ", " + Num(q.z(), 5) + ", " + Num(q.w(), 5);
}

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
.plots img, .grid img { border: 1px solid #ddd; background: white; }
.plots { display: flex; flex-wrap: wrap; gap: 10px; align-items: flex-start; }
.grid { display: flex; flex-wrap: wrap; gap: 10px; }
figure { margin: 0; background: white; border: 1px solid #e2e2e2; padding: 4px; }
figure.outlier { border: 2px solid #d33; }
figure.rejected { border: 2px solid #e08a00; }
figcaption { font-size: 12px; color: #333; max-width: 320px; }
.bad { color: #c22; font-weight: 600; }
.small { font-size: 12px; color: #555; }
)";

std::string Swatch(int camera) {
  const cv::Scalar c = CameraColor(camera);  // BGR
  char buf[96];
  std::snprintf(buf, sizeof buf,
                "<span class=\"swatch\" style=\"background: rgb(%d,%d,%d)\"></span>", int(c[2]),
                int(c[1]), int(c[0]));
  return buf;
}

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
double PointSigmaMm(const CameraResult& cam, double depth_m) {
  const Eigen::Vector3d p = cam.T_cam.linear() * Eigen::Vector3d(0, 0, depth_m);  // m, from the camera centre
  Eigen::Matrix<double, 3, 6> J;
  J.leftCols<3>().setIdentity();
  Eigen::Matrix3d skew;
  skew << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0;
  J.rightCols<3>() = -skew * (M_PI / 180.0) * 1000.0;  // mm per degree of rotation
  return std::sqrt(std::max(0.0, (J * cam.sigma->covariance * J.transpose()).trace()));
}

void UncertaintyTable(const ReportModel& model, std::ostringstream& out) {
  bool any = false;
  for (const CameraModel& cam : model.cameras) any = any || cam.result->sigma;
  if (!any) return;
  out << "<h3>How well each camera is known (1σ)</h3>\n<table>\n<tr><th class=\"name\">camera</th>"
      << "<th>position<br>± mm</th><th>orientation<br>± °</th><th>point 1 m in front<br>± mm</th>"
      << "<th>point 3 m in front<br>± mm</th></tr>\n";
  for (size_t k = 0; k < model.cameras.size(); ++k) {
    const CameraResult& cam = *model.cameras[k].result;
    if (!cam.sigma) continue;
    out << "<tr><td class=\"name\">" << Swatch(static_cast<int>(k)) << Escape(cam.name) << "</td><td>"
        << Num(cam.sigma->position_mm, 2) << "</td><td>" << Num(cam.sigma->rotation_deg, 4) << "</td><td>"
        << Num(PointSigmaMm(cam, 1.0), 2) << "</td><td>" << Num(PointSigmaMm(cam, 3.0), 2) << "</td></tr>\n";
  }
  out << "</table>\n";
  out << "<p class=\"small\">From the covariance of the solution, scaled by the residuals seen "
         "(robot pose error and detection noise included). ± mm is the RMS error over the three axes "
         "together; a point in front of a camera is where the camera puts something it sees at that "
         "distance.";
  if (model.result->target_sigma)
    out << " The target on the " << (model.result->setup == Setup::kEyeToHand ? "flange" : "base")
        << ": ± " << Num(model.result->target_sigma->position_mm, 2) << " mm, ± "
        << Num(model.result->target_sigma->rotation_deg, 4) << "°.";
  out << "</p>\n";
  bool validated = false;
  for (const CameraModel& cam : model.cameras) validated = validated || cam.result->cross_validation;
  if (validated) {
    out << "<h3>Held out (calibrate --cross-validate)</h3>\n<table>\n<tr><th class=\"name\">camera</th>"
        << "<th>poses left out</th><th>held-out RMS<br>(px)</th><th>in-sample RMS<br>(px)</th>"
        << "<th>spread over the folds<br>(mm / °)</th></tr>\n";
    for (size_t k = 0; k < model.cameras.size(); ++k) {
      const CameraResult& cam = *model.cameras[k].result;
      if (!cam.cross_validation) continue;
      const auto& cv = *cam.cross_validation;
      out << "<tr><td class=\"name\">" << Swatch(static_cast<int>(k)) << Escape(cam.name) << "</td><td>" << cv.folds
          << "</td><td>" << Num(cv.held_out_rms_px, 3) << "</td><td>" << Num(cam.rms_px, 3) << "</td><td>"
          << Num(cv.position_spread_mm, 3) << " / " << Num(cv.rotation_spread_deg, 4) << "</td></tr>\n";
    }
    out << "</table>\n<p class=\"small\">Each robot pose left out in turn, the solve run again without "
           "it and its views predicted. A held-out RMS far above the in-sample one means over-fitting or "
           "bad poses; the spread is how far one pose moves each camera.</p>\n";
  }
}

// Refined (or estimated) intrinsics beside the given ones.
void IntrinsicsTable(const ReportModel& model, std::ostringstream& out) {
  bool any = false;
  for (const CameraModel& cam : model.cameras) any = any || cam.result->intrinsics;
  if (!any) return;
  out << "<h3>Intrinsics</h3>\n<table>\n<tr><th class=\"name\">camera</th><th>parameter</th><th>given</th>"
      << "<th>refined ± 1σ</th><th>change</th></tr>\n";
  for (size_t k = 0; k < model.cameras.size(); ++k) {
    const CameraModel& cam = model.cameras[k];
    if (!cam.result->intrinsics) continue;
    const IntrinsicsResult& in = *cam.result->intrinsics;
    const Camera* given = nullptr;
    for (const Camera& c : model.given_cameras)
      if (c.name == cam.camera->name) given = &c;
    for (const std::string& name : in.refined) {
      int p = 0;
      while (p < OpenCVCameraModel::kNumParams && name != Camera::ParamName(p)) ++p;
      if (p == OpenCVCameraModel::kNumParams) continue;
      const int decimals = p < 4 ? 2 : 5;
      const bool known = given && given->has_intrinsics;
      const bool undetermined =
          std::find(in.undetermined.begin(), in.undetermined.end(), name) != in.undetermined.end();
      out << "<tr" << (undetermined ? " class=\"flag\"" : "") << "><td class=\"name\">" << Swatch(static_cast<int>(k))
          << Escape(cam.camera->name) << "</td><td>" << Escape(name) << "</td><td>"
          << (known ? Num(given->params[p], decimals) : "–") << "</td><td>" << Num(in.camera.params[p], decimals)
          << " ± " << Num(in.sigma[p], decimals) << "</td><td>"
          << (known ? Num(in.camera.params[p] - given->params[p], decimals) : "estimated") << "</td></tr>\n";
    }
  }
  out << "</table>\n<p class=\"small\">Intrinsics that were unknowns of the joint solve "
         "(--refine-intrinsics, or a camera given none). Highlighted: the views hardly determine "
         "them; a prior keeps them near the given value.</p>\n";
}

void CameraTables(const ReportModel& model, std::ostringstream& out) {
  const bool eye_to_hand = model.dataset->setup == Setup::kEyeToHand;
  const std::string T = eye_to_hand ? "T_base_cam" : "T_ee_cam";
  const std::string frame = eye_to_hand ? "base" : "ee";
  auto flagged = [&](const CameraModel& cam) {
    for (const auto& w : model.warnings)
      if (w.rfind("camera '" + cam.camera->name + "'", 0) == 0) return true;
    return false;
  };
  out << "<h3>Camera poses " << T
      << "</h3>\n<table>\n<tr><th class=\"name\">camera</th><th>x, y, z (mm)</th>"
      << "<th>roll, pitch, yaw (°)</th><th>quaternion x, y, z, w</th></tr>\n";
  for (size_t k = 0; k < model.cameras.size(); ++k) {
    const CameraModel& cam = model.cameras[k];
    out << "<tr><td class=\"name\">" << Swatch(static_cast<int>(k)) << Escape(cam.camera->name)
        << "</td>";
    if (cam.result->calibrated) {
      const Eigen::Isometry3d& Tc = cam.result->T_cam;
      out << "<td>" << Triple(1000.0 * Tc.translation(), 2) << "</td><td>"
          << Triple(RollPitchYaw(Tc.rotation()) * (180.0 / M_PI), 3) << "</td><td>" << Quaternion(Tc.rotation())
          << "</td>";
    } else {
      out << "<td colspan=\"3\" class=\"name bad\">not calibrated</td>";
    }
    out << "</tr>\n";
  }
  out << "</table>\n<p class=\"small\">" << T
      << " is the pose of the camera (OpenCV optical frame: x right, y "
      << "down, z forward) in the " << frame << " frame; it maps camera coordinates to " << frame
      << " coordinates. Roll, pitch, yaw are fixed-axis x, y, z angles: R = "
         "Rz(yaw)·Ry(pitch)·Rx(roll).</p>\n";

  // The closed form the result was compared with (Calibrate() names it per camera).
  std::string closed_form;
  for (const CameraModel& cam : model.cameras)
    if (cam.result->closed_form && model.show_closed_form) closed_form = cam.result->closed_form->method;
  out << "<h3>Quality per camera</h3>\n<table>\n<tr><th class=\"name\">camera</th><th>views used "
         "/<br>rejected / "
      << "outliers</th><th>RMS<br>(px)</th><th>max<br>(px)</th><th>AX=ZB e<sub>t</sub><br>in " << frame
      << " (mm)</th><th>AX=ZB e<sub>θ</sub><br>(°)</th><th>rotation<br>spread (°)</th><th>axis<br>spread "
         "(°)</th>";
  if (!closed_form.empty())
    out << "<th>vs " << Escape(closed_form) << " closed form<br>Δt (mm) / Δθ (°) / Δ (px)</th>";
  out << "</tr>\n";
  for (size_t k = 0; k < model.cameras.size(); ++k) {
    const CameraModel& cam = model.cameras[k];
    const CameraResult& r = *cam.result;
    out << "<tr" << (flagged(cam) ? " class=\"flag\"" : "") << "><td class=\"name\">"
        << Swatch(static_cast<int>(k)) << Escape(cam.camera->name) << "</td><td>" << cam.used
        << " / " << cam.rejected << " / " << r.outliers << "</td>";
    if (r.calibrated) {
      out << "<td>" << Num(r.rms_px, 3) << "</td><td>" << Num(r.max_px, 3) << "</td>";
      if (r.axzb.views)
        out << "<td>" << Num(r.axzb.camera_frame_mm, 2) << "</td><td>" << Num(r.axzb.rotation_deg, 3) << "</td>";
      else
        out << "<td>–</td><td>–</td>";
    } else {
      out << "<td>–</td><td>–</td><td>–</td><td>–</td>";
    }
    out << "<td>" << Num(r.rotation_spread_deg, 1) << "</td><td>" << Num(r.axis_spread_deg, 1) << "</td>";
    if (!closed_form.empty()) {
      if (!r.closed_form)
        out << "<td class=\"small\">not compared</td>";
      else if (r.closed_form->available)
        out << "<td>" << Num(r.closed_form->translation_mm, 2) << " / " << Num(r.closed_form->rotation_deg, 3)
            << " / " << Num(r.closed_form->displacement_px, 2) << "</td>";
      else
        out << "<td class=\"small\">" << Escape(r.closed_form->why_not) << "</td>";
    }
    out << "</tr>\n";
  }
  out << "</table>\n<p class=\"small\">Highlighted rows have warnings. RMS and max: reprojection "
         "error of the used "
      << "views through the calibrated chain. AX=ZB: mean disagreement between where each view's own PnP "
         "pose and the chain put the camera, in the " << frame << " frame (the paper's form, in the target "
         "frame, adds the lever arm to the " << frame << " origin: "
      << Num(model.result->metrics.axzb_translation_mm, 2) << " mm over all cameras). Rotation spread: the largest robot rotation between two of the camera's poses; "
         "axis spread: the "
      << "largest angle between the rotation axes of those motions (hand-eye needs both large).";
  if (!closed_form.empty())
    out << " Closed form: " << Escape(closed_form)
        << "'s per-camera hand-eye; Δ (px) is how far the camera's detected points move in the "
           "image when seen from the closed form's camera pose instead of the result's (what the "
           "data can tell apart; the mm and degrees include directions the images barely "
           "constrain).";
  out << "</p>\n";
}

void TransformRow(const std::string& name, const Eigen::Isometry3d& T, std::ostringstream& out) {
  out << "<tr><td class=\"name\">" << name << "</td><td>" << Triple(1000.0 * T.translation(), 2)
      << "</td><td>" << Triple(RollPitchYaw(T.rotation()) * (180.0 / M_PI), 3) << "</td><td>"
      << Quaternion(T.rotation()) << "</td>";
}

void SharedAndPairs(const ReportModel& model, std::ostringstream& out) {
  const CalibrationResult& result = *model.result;
  const bool eye_to_hand = model.dataset->setup == Setup::kEyeToHand;
  const std::string Z = eye_to_hand ? "T_ee_target" : "T_base_target";
  out << "<h3>Shared transform " << Z
      << "</h3>\n<table><tr><th class=\"name\">transform</th><th>x, y, z (mm)</th>"
      << "<th>roll, pitch, yaw (°)</th><th>quaternion x, y, z, w</th></tr>\n";
  TransformRow(Z, result.T_target, out);
  out << "</tr>\n";
  for (const CameraModel& cam : model.cameras)
    if (cam.result->own_T_target) {
      TransformRow(Z + " (" + Escape(cam.camera->name) + "'s own)", *cam.result->own_T_target, out);
      out << "</tr>\n";
    }
  out << "</table>\n";

  out << "<h3>Camera pairs T_camk_camt</h3>\n";
  if (result.camera_pairs.empty()) {
    out << "<p class=\"small\">No camera pairs in the result.</p>\n";
    return;
  }
  out << "<table><tr><th class=\"name\">transform</th><th>x, y, z (mm)</th><th>roll, pitch, yaw "
         "(°)</th>"
      << "<th>quaternion x, y, z, w</th><th>baseline (mm)</th><th>shared views</th>"
      << "<th>vs chain through the " << (eye_to_hand ? "base" : "flange")
      << "<br>Δt (mm) / Δθ (°)</th></tr>\n";
  for (const CameraPairResult& p : result.camera_pairs) {
    TransformRow("T_" + Escape(p.camera_k) + "_" + Escape(p.camera_t), p.T_camk_camt, out);
    out << "<td>" << Num(1000.0 * p.T_camk_camt.translation().norm(), 2) << "</td><td>"
        << p.shared_views << "</td>";
    const int k = model.dataset->CameraIndex(p.camera_k),
              t = model.dataset->CameraIndex(p.camera_t);
    const CameraResult* ck = k >= 0 ? model.cameras[k].result : nullptr;
    const CameraResult* ct = t >= 0 ? model.cameras[t].result : nullptr;
    if (ck && ct && ck->calibrated && ct->calibrated) {
      // T_camk_camt = X_k · X_t⁻¹ = T_cam_base(k) · T_base_cam(t) when the pair agrees with the
      // cameras.
      const Eigen::Isometry3d chain = ck->T_cam.inverse() * ct->T_cam;
      out << "<td>" << Num(1000.0 * (chain.translation() - p.T_camk_camt.translation()).norm(), 3)
          << " / "
          << Num(RotationDistance(chain.rotation(), p.T_camk_camt.rotation()) * 180.0 / M_PI, 4)
          << "</td>";
    } else {
      out << "<td>–</td>";
    }
    out << "</tr>\n";
  }
  out << "</table>\n<p class=\"small\">T_camk_camt maps camera t's coordinates into camera k's. "
         "The joint solve "
         "estimates each pair as its own unknown (the paper's c<sub>cross</sub> terms); the last "
         "column compares it "
         "with the pair implied by the two cameras' own poses.</p>\n";
}

}  // namespace

std::string RenderHtml(const ReportModel& model, const PlotFiles& plots,
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
      << (result.setup == Setup::kEyeToHand ? "base" : "ee") << " frame) / <b>"
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
    for (const auto& w : model.warnings) out << "<li>" << Escape(w) << "</li>\n";
    out << "</ul>\n";
  }

  out << "<h2 id=\"cameras\">Cameras</h2>\n";
  CameraTables(model, out);
  UncertaintyTable(model, out);
  IntrinsicsTable(model, out);
  SharedAndPairs(model, out);

  out << "<h2 id=\"plots\">Plots</h2>\n<div class=\"plots\">\n<img src=\"" << plots.map
      << "\" alt=\"map of the cell from above\">\n<img src=\"" << plots.view_rms
      << "\" alt=\"RMS per view over the poses\">\n</div>\n<h3>Residual histograms</h3>\n<div "
         "class=\"plots\">\n";
  for (size_t k = 0; k < plots.histograms.size(); ++k)
    out << "<img src=\"" << plots.histograms[k] << "\" alt=\"residual histogram of "
        << Escape(model.cameras[k].camera->name) << "\">\n";
  out << "</div>\n<h3>Residuals in the image plane</h3>\n<div class=\"plots\">\n";
  for (size_t k = 0; k < plots.image_plane.size(); ++k)
    out << "<img src=\"" << plots.image_plane[k] << "\" alt=\"image-plane residuals of "
        << Escape(model.cameras[k].camera->name) << "\">\n";
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
