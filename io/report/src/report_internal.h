// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Internal pieces of the report writer (report.h), shared by its files:
// the model (what every view and camera looks like under the result), the
// overlays, the plots and the HTML.

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <vector>

#include "handeye/core/calibration.h"
#include "handeye/core/dataset.h"
#include "handeye/report/report.h"

namespace handeye::report {

/// Camera k's points at one pose as predicted through another camera t of the
/// same pose and the pair transform (the paper's c_cross):
/// p_camk = T_camk_camt · X_t · M_j · Z · p_target.
struct CrossPrediction {
  int other_camera = 0;
  std::vector<std::optional<Eigen::Vector2d>> predicted_px;  ///< per point of the view
  double rms_px = 0;
};

/// One view (an observation) under the result.
struct ViewModel {
  int camera = 0;
  int pose = 0;  ///< index in dataset.poses
  const Observation* observation = nullptr;
  std::vector<Eigen::Vector3d> p_target;  ///< target points of the detected ids
  /// X_k · M_j · Z: the target's pose in the camera through the calibrated
  /// chain; absent when the camera was not calibrated.
  std::optional<Eigen::Isometry3d> T_cam_target;
  /// Per detected point: its projection through the chain (absent behind the camera).
  std::vector<std::optional<Eigen::Vector2d>> predicted_px;
  std::vector<double> residual_px;  ///< |detected − predicted|, per predicted point
  double rms_px = 0, max_px = 0;
  bool used = true;      ///< from the result: used by the solver
  bool outlier = false;  ///< from the result: down-weighted by the robust loss
  std::string rejected_because;
  std::vector<CrossPrediction> cross;
  /// Target pose from the detected points alone (PnP), for AX = ZB.
  std::optional<Eigen::Isometry3d> T_cam_target_pnp;

  /// Folder-safe names, unique per report.
  std::string overlay_path;  ///< relative to the report folder
  std::string thumb_path;
};

/// The per-camera closed-form comparison.
struct ClosedFormComparison {
  bool available = false;
  std::string why_not;        ///< when not available
  double translation_mm = 0;  ///< |t_joint − t_closed| of T_base_cam / T_ee_cam
  double rotation_deg = 0;
  /// Mean image displacement of the detected points seen from the closed
  /// form's camera pose instead of the result's (see ReportOptions).
  double displacement_px = 0;
};

struct CameraModel {
  const Camera* camera = nullptr;
  const CameraResult* result = nullptr;  ///< never null after BuildModel
  std::vector<int> views;                ///< indices into ReportModel::views
  int used = 0, rejected = 0, outliers = 0;
  double rms_px = 0, max_px = 0;  ///< over used views, recomputed
  double axzb_translation_mm = 0, axzb_rotation_deg = 0;
  int axzb_views = 0;
  double rotation_spread_deg = 0;  ///< largest rotation between two used poses
  double axis_spread_deg = 0;      ///< largest angle between relative-motion axes
  ClosedFormComparison closed_form;
  std::string folder;  ///< folder-safe name
};

/// Everything the overlays, plots and HTML draw, computed once.
struct ReportModel {
  const Dataset* dataset = nullptr;  ///< with the intrinsics the result used
  std::vector<Camera> given_cameras;  ///< the dataset's own, before any refinement
  const CalibrationResult* result = nullptr;
  std::string closed_form_method;  ///< name of the method compared with, "" when not run
  std::vector<ViewModel> views;    ///< dataset.observations order
  std::vector<CameraModel> cameras;
  /// Colour scale of residuals (pixels): 0 … residual_scale_max_px, shared by
  /// every overlay and plot so colours mean the same everywhere.
  double residual_scale_max_px = 1.0;
  /// 99th percentile of the used views' point residuals (pixels): the range
  /// of the histograms and the magnification of the image-plane plots.
  double residual_p99_px = 0.0;
  std::vector<std::string> warnings;
  std::vector<std::string> notes;
};

/// Builds the model; throws InputError when result and dataset do not match.
ReportModel BuildModel(const Dataset& dataset, const CalibrationResult& result,
                       const ReportOptions& options);

/// Fixed-axis roll, pitch, yaw (degrees) with R = Rz(yaw)·Ry(pitch)·Rx(roll),
/// as in handeye-result/1's summaries.
Eigen::Vector3d RollPitchYawDeg(const Eigen::Matrix3d& R);

/// `name` reduced to [A-Za-z0-9._-] (others become '_'), never empty, never "." or "..".
std::string SafeFileName(const std::string& name);

// --- Drawing ---------------------------------------------------------------

/// The overlay of one view, drawn on `gray` (8-bit, camera size; empty: a
/// neutral canvas). Colour BGR image of the camera's size.
cv::Mat DrawOverlay(const ReportModel& model, const ViewModel& view, const cv::Mat& gray);

/// Colour of a residual (pixels) on the report's scale: green (0) → yellow → red (≥ max).
cv::Scalar ResidualColor(double residual_px, double scale_max_px);
/// A distinct colour per camera index (BGR).
cv::Scalar CameraColor(int camera);

/// Writes the plots into `dir`/plots/ and returns their paths relative to `dir`:
/// entries named "histogram/<camera>", "image_plane/<camera>", "view_rms", "map".
struct PlotFiles {
  std::vector<std::string> histograms;   ///< per camera (model order)
  std::vector<std::string> image_plane;  ///< per camera
  std::string view_rms;
  std::string map;
};
PlotFiles WritePlots(const ReportModel& model, const std::string& dir);

/// The HTML page.
std::string RenderHtml(const ReportModel& model, const PlotFiles& plots,
                       const ReportOptions& options);

}  // namespace handeye::report
