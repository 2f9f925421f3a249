// SPDX-License-Identifier: GPL-2.0-or-later
// The report's tables: camera poses and quality per camera, uncertainty,
// refined intrinsics, the shared transform and the camera pairs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "handeye/core/transform.h"
#include "handeye/core/setup_frames.h"
#include "report_html.h"

namespace handeye::report {
namespace {

double PointSigmaMm(const CameraResult& cam, double depth_m) {
  const Eigen::Vector3d p = cam.T_cam.linear() * Eigen::Vector3d(0, 0, depth_m);  // m, from the camera centre
  Eigen::Matrix<double, 3, 6> J;
  J.leftCols<3>().setIdentity();
  Eigen::Matrix3d skew;
  skew << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0;
  J.rightCols<3>() = -skew * (M_PI / 180.0) * 1000.0;  // mm per degree of rotation
  return std::sqrt(std::max(0.0, (J * cam.sigma->covariance * J.transpose()).trace()));
}

void TransformRow(const std::string& name, const Eigen::Isometry3d& T, std::ostringstream& out) {
  out << "<tr><td class=\"name\">" << name << "</td><td>" << Triple(1000.0 * T.translation(), 2)
      << "</td><td>" << Triple(RollPitchYaw(T.rotation()) * (180.0 / M_PI), 3) << "</td><td>"
      << Quaternion(T.rotation()) << "</td>";
}

}  // namespace

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
    out << " The target on the " << FramesOf(model.result->setup).holder_in_words
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
  const SetupFrames frames = FramesOf(model.dataset->setup);
  const std::string& T = frames.camera_key;
  const std::string& frame = frames.mount;
  // A row is flagged by the warnings about its camera as a whole, not by
  // those about one view or pose of it.
  auto flagged = [&](const CameraModel& cam) {
    for (const Warning& w : model.warnings)
      if (w.camera == cam.camera->name && w.pose.empty() && !w.view) return true;
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

void SharedAndPairs(const ReportModel& model, std::ostringstream& out) {
  const CalibrationResult& result = *model.result;
  const SetupFrames frames = FramesOf(model.dataset->setup);
  const std::string& Z = frames.target_key;
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
      << "<th>vs chain through the " << frames.mount_in_words
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

}  // namespace handeye::report
