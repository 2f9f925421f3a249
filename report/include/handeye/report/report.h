// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The calibration report (SPEC §7 `handeye report`): per-view overlay PNGs
/// and a self-contained `index.html` with the plots that a person reads to
/// accept or reject a calibration. Everything is drawn off-screen: the
/// overlays with OpenCV, the plots as inline SVG; the HTML needs no network
/// and no JavaScript.
///
/// Layout of the report folder:
///  - `index.html`                         summary, warnings, plots (inline SVG:
///                                         residual histograms, image-plane
///                                         residuals, per-view RMS, cell map),
///                                         thumbnails
///  - `overlays/<camera>/<pose>.png`       one full-resolution overlay per view
///  - `thumbs/<camera>/<pose>.jpg`         the same, `thumbnail_width_px` wide
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

  /// Show the result's comparison of each camera with a per-camera closed
  /// form (CameraResult::closed_form) in the camera table. The warnings are
  /// the result's own (CalibrationOptions::warn decides them), all shown.
  bool compare_closed_form = true;

  /// "What to capture next": the robot poses to record next that most reduce
  /// the worst camera's σ, as `handeye advise` proposes them
  /// (core/plan_advice.h), with the σ predicted after each. At most
  /// `next_poses` (0 leaves the section out); with `next_goal_mm` > 0 the
  /// cameras predicted above it are named and the proposals stop once all
  /// are within it.
  int next_poses = 4;
  double next_goal_mm = 0;

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
  /// The result's warnings (also in the HTML), after any about the result
  /// not matching the dataset's observations.
  std::vector<Warning> warnings;
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
