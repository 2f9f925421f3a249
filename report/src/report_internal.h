// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Internal pieces of the report writer (report.h), shared by its files:
// the model (what every view and camera looks like under the result), the
// overlays, the plots (SVG) and the HTML.

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <vector>

#include "handeye/core/calibration.h"
#include "handeye/core/dataset.h"
#include "handeye/core/plan_advice.h"
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
  double rms_px = 0, max_px = 0;  ///< the result's (recomputed when it lacks the view)
  bool used = true;      ///< from the result: used by the solver
  bool outlier = false;  ///< from the result: down-weighted by the robust loss
  std::string rejected_because;
  std::vector<CrossPrediction> cross;

  /// Folder-safe names, unique per report.
  std::string overlay_path;  ///< relative to the report folder
  std::string thumb_path;
};

struct CameraModel {
  const Camera* camera = nullptr;
  /// Never null after BuildModel; its figures (rms_px, max_px, axzb, spreads,
  /// closed_form) are what the report shows.
  const CameraResult* result = nullptr;
  std::vector<int> views;  ///< indices into ReportModel::views
  int used = 0, rejected = 0;
  std::string folder;  ///< folder-safe name
};

/// The "what to capture next" section (ReportOptions::next_poses): the advice,
/// or why there is none.
struct NextCapture {
  bool wanted = false;  ///< next_poses > 0
  std::string why_not;  ///< no advice could be computed: why
  PlanCell cell;        ///< the cell as the result knows it
  Advice advice;
  double goal_mm = 0;
};

/// Advice on the poses to record next (core/plan_advice.h); never throws
/// for data it cannot advise on (why_not says why).
NextCapture AdviseNext(const Dataset& dataset, const CalibrationResult& result,
                       const ReportOptions& options);

/// Everything the overlays, plots and HTML draw, computed once.
struct ReportModel {
  const Dataset* dataset = nullptr;  ///< with the intrinsics the result used
  std::vector<Camera> given_cameras;  ///< the dataset's own, before any refinement
  const CalibrationResult* result = nullptr;
  bool show_closed_form = true;  ///< ReportOptions::compare_closed_form
  std::vector<ViewModel> views;    ///< dataset.observations order
  std::vector<CameraModel> cameras;
  /// Colour scale of residuals (pixels): 0 … residual_scale_max_px, shared by
  /// every overlay and plot so colours mean the same everywhere.
  double residual_scale_max_px = 1.0;
  /// 99th percentile of the used views' point residuals (pixels): the range
  /// of the histograms and the magnification of the image-plane plots.
  double residual_p99_px = 0.0;
  /// The result's warnings, after any about the result not matching the observations.
  std::vector<Warning> warnings;
  std::vector<std::string> notes;
  NextCapture next;
};

/// Builds the model; throws InputError when result and dataset do not match.
ReportModel BuildModel(const Dataset& dataset, const CalibrationResult& result,
                       const ReportOptions& options);

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

/// The plots as inline SVG elements for index.html.
struct Plots {
  std::vector<std::string> histograms;   ///< residual histogram per camera (model order)
  std::vector<std::string> image_plane;  ///< residuals in the image plane per camera
  std::string view_rms;                  ///< RMS per view over the poses
  std::string map;                       ///< the cell from above
};
Plots DrawPlots(const ReportModel& model);

/// Smallest 1, 2 or 5 × 10^k ≥ `value`; 1 for a value that is not finite and positive.
double NiceCeil(double value);
/// Largest 1, 2 or 5 × 10^k ≤ `value`; 1 for a value that is not finite and positive.
double NiceFloor(double value);

/// The HTML page.
std::string RenderHtml(const ReportModel& model, const Plots& plots,
                       const ReportOptions& options);

}  // namespace handeye::report
