// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The calibration report (SPEC §7 `handeye report`): per-view overlay PNGs,
/// plots and a self-contained `index.html` that a person reads to accept or
/// reject a calibration. Everything is drawn off-screen with OpenCV; the HTML
/// needs no network and no JavaScript.
///
/// Layout of the report folder:
///  - `index.html`                         summary, warnings, plots, thumbnails
///  - `overlays/<camera>/<pose>.png`       one full-resolution overlay per view
///  - `thumbs/<camera>/<pose>.jpg`         the same, `thumbnail_width_px` wide
///  - `plots/*.png`                        residual histograms, image-plane
///                                         residuals, per-view RMS, cell map
/// (camera names and pose ids are reduced to `[A-Za-z0-9._-]` in file names).

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "handeye/core/calibration.h"
#include "handeye/core/dataset.h"

namespace handeye {

struct ReportOptions {
  /// Worker threads for the overlays (one image in memory per thread); 0 = all cores.
  int threads = 0;
  /// Width of the JPEG thumbnails, pixels.
  int thumbnail_width_px = 320;

  // --- Warning thresholds ----------------------------------------------------
  /// A camera with fewer used views is flagged: hand-eye needs two motions
  /// with non-parallel axes in theory, but with fewer than about ten poses a
  /// single bad pose moves the result visibly (Tsai & Lenz 1989 recommend
  /// well over the minimum).
  int min_views_per_camera = 10;
  /// Robot rotation diversity of one camera's views: the largest rotation
  /// between two of its poses (degrees) below which it is flagged. Tsai and
  /// Lenz show the translation error grows roughly as 1/(rotation angle)
  /// between poses; below 20° it is 3× that of a 60° spread.
  double min_rotation_spread_deg = 20.0;
  /// The largest angle between the rotation axes of two of its relative
  /// motions (degrees, axes folded into [0°, 90°]) below which it is flagged:
  /// the rotation error grows like 1/sin(axis angle), 2× at 30°.
  double min_axis_spread_deg = 30.0;
  /// A camera whose RMS reprojection error through the calibrated chain
  /// exceeds this (pixels) is flagged: corner detectors reach 0.1–0.3 px, so
  /// more than 1 px means a model, robot or detection problem.
  double max_camera_rms_px = 1.0;
  /// Compare each camera with a per-camera closed form (Park & Martin; ViSP
  /// when the result itself is Park) and flag disagreement.
  bool compare_closed_form = true;
  /// Disagreement threshold, pixels: the mean displacement of the camera's
  /// detected target points (placed by the result's chain) when seen from the
  /// closed form's camera pose instead of the result's. A closed form's error
  /// lies mostly along what the images barely constrain (the camera turning
  /// about the target), so millimetres and degrees would flag good results;
  /// the displacement is what the data can see. In simulated cells with
  /// realistic robot noise (0.5–1 mm, 0.05–0.1°) it stays below 1 px while
  /// the closed form is off by up to 9 mm and 0.2°; a wrong solution (another
  /// local minimum, a camera moved during the session) moves points by tens.
  double max_closed_form_disagreement_px = 5.0;

  /// Shown in the report's header (e.g. the file names the data came from).
  std::string dataset_label, result_label;
  /// Called after each overlay with (done, total), from one thread at a time.
  std::function<void(std::size_t, std::size_t)> progress;

  bool Check(std::string* why) const;
};

/// What WriteReport wrote.
struct ReportSummary {
  std::string index_html;             ///< path of DIR/index.html
  int overlays = 0;                   ///< overlay PNGs written
  std::vector<std::string> warnings;  ///< the report's warnings (also in the HTML)
  double seconds = 0;                 ///< wall time
};

/// Writes the report for `result` into folder `dir` (created if missing;
/// files of an earlier report are overwritten, index.html last and
/// atomically, so it never links to a file that is not there yet).
///
/// `dataset` must hold the observations the result was computed from (run
/// DetectAll on a dataset that has only images). Views whose pose lists an
/// image for the camera are drawn on that image; the others on a neutral
/// grey canvas of the camera's size. Throws InputError when the result does
/// not belong to the dataset (setup or camera names differ) or an image is
/// missing or unreadable, and when `dir` cannot be written.
ReportSummary WriteReport(const Dataset& dataset, const CalibrationResult& result,
                          const std::string& dir, const ReportOptions& options = {});

}  // namespace handeye
