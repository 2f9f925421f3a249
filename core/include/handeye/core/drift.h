// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Has a camera moved since calibration? A few new robot poses with images
/// and an existing result: with the shared transform held, each camera's pose
/// is estimated again from its new views alone and compared with its
/// calibrated pose (SPEC §7 `handeye check`).

#include <string>
#include <vector>

#include "handeye/core/calibration.h"

namespace handeye {

struct DriftOptions {
  double tolerance_mm = 1.0;   ///< a camera moved when its centre moved more …
  double tolerance_deg = 0.1;  ///< … or it turned more than this
  int min_views = 2;           ///< fewer usable new views: "not_assessed"
  int threads = 1;
  /// False, with the reason, for non-positive tolerances or min_views < 1.
  bool Check(std::string* why) const;
};

/// One camera's verdict.
struct CameraDrift {
  std::string name;
  /// "moved": beyond a tolerance and by more than 3σ (or as unlikely, where
  /// σ holds a robot σ estimated from few poses: Student's t); "ok": within the
  /// tolerances; "not_assessed": the new data cannot tell (`reason` says why:
  /// too few new views, not calibrated in the result, or a move beyond a
  /// tolerance that the check's noise could explain).
  std::string verdict;
  std::string reason;    ///< why not_assessed; empty otherwise
  double moved_mm = 0;   ///< distance between the calibrated and the new camera centre
  double moved_deg = 0;  ///< angle between the calibrated and the new orientation
  /// 1σ of the move (sqrt of the trace, as PoseUncertainty): the new
  /// estimate's, and the calibration's own (the result's sigma without what
  /// the given intrinsics add) as far as the target, held as calibrated,
  /// does not carry it into the new estimate too.
  double sigma_mm = 0;
  double sigma_deg = 0;
  int views = 0;  ///< new views used
  /// True when the camera was estimated from its new views (moved_*,
  /// sigma_* and T_cam hold the estimate); false for "not_assessed" cameras
  /// without enough views or not calibrated.
  bool estimated = false;
  /// The camera's pose now (eye_to_hand: T_base_cam; eye_in_hand: T_ee_cam).
  Eigen::Isometry3d T_cam = Eigen::Isometry3d::Identity();
};

struct DriftResult {
  std::vector<CameraDrift> cameras;  ///< result order
  std::vector<Warning> warnings;
  bool AnyMoved() const;
  /// True when some camera is "not_assessed".
  bool AnyNotAssessed() const;
};

/// Checks every calibrated camera of `calibration` against the new views of
/// `dataset` (its observations; detect first). The dataset's intrinsics are
/// replaced by the result's where it refined them. Throws InputError when the
/// dataset and the result do not describe the same cell (setup, cameras).
DriftResult CheckDrift(const Dataset& dataset, const CalibrationResult& calibration, const DriftOptions& options);

}  // namespace handeye
