// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// A warning as a record a program can act on: what kind it is, which camera,
/// robot pose and view it is about, and the sentence a person reads. Nothing
/// downstream parses the sentence; the result file keeps the sentences in
/// `warnings` and the records in `warning_details` (docs/formats.md).

#include <optional>
#include <string>
#include <vector>

namespace handeye {

/// What a warning is about. Each kind has a stable snake_case name
/// (WarningKindName) that files and programs use; new kinds are only added.
enum class WarningKind {
  kOther,  ///< a warning of a file that had no details (written before they existed)
  // Input (dataset loader, importers, detection).
  kTargetAmbiguous,    ///< the target's layout is ambiguous (a checkerboard with cols + rows even)
  kTargetMismatch,     ///< images show a target other than the declared one
  kRepeatedImages,     ///< one image file under several robot poses
  kPoseFilesDisagree,  ///< METRIC pose files of one name that differ
  // Calibration: cameras left out.
  kCameraNotSeen,        ///< the camera never saw the target
  kCameraNoUsableViews,  ///< the target was detected, but no view was usable
  kCameraMethodFailed,   ///< the chosen closed form could not calibrate the camera
  // Calibration: views and poses.
  kViewLeftOut,          ///< one view left out (its reason in the text)
  kObliqueViewsLeftOut,  ///< views seen too obliquely, all named in the text
  kPoseRecordMismatch,   ///< a robot pose that disagrees with all its views
  kManyViewsOff,         ///< many views far off the others, kept: the model is suspect
  // Calibration: solve and model.
  kNotConverged,            ///< the solver stopped at the iteration limit
  kIntrinsicsUndetermined,  ///< refined intrinsics the views hardly determine
  kIntrinsicsOff,           ///< the views find the given focal length or principal point off
  // Calibration: quality of one camera (CalibrationOptions::warn).
  kFewViews,
  kPoorRotationSpread,  ///< the views differ little in robot rotation
  kPoorRotationAxes,    ///< the motions turn about nearly one axis
  kLargeResiduals,
  kOutlierViews,         ///< views down-weighted by the robust loss
  kClosedFormDisagrees,  ///< the result and a per-camera closed form disagree
  // Drift check.
  kDriftNotChecked,   ///< too few new views, or not calibrated
  kDriftWithinNoise,  ///< beyond a tolerance, but within the check's noise
  kDriftTooCoarse,    ///< the new views know the camera too coarsely for the tolerance
  // Export and report.
  kCameraNotExported,   ///< an uncalibrated camera left out of an export
  kResultViewsMissing,  ///< the report's observations hold views the result does not
  // New kinds go above this line: tests walk the kinds up to kResultViewsMissing.
};

/// The stable name of a kind, e.g. "view_left_out".
const char* WarningKindName(WarningKind kind);
/// The kind of a name WarningKindName gives; nullopt for any other string.
std::optional<WarningKind> ParseWarningKind(const std::string& name);

/// One warning. `camera`, `pose` and `view` say what it is about; each is
/// empty (or nullopt) when the warning is not about one camera, pose or view.
struct Warning {
  WarningKind kind = WarningKind::kOther;
  std::string camera;  ///< the camera's name
  std::string pose;    ///< the robot pose's id
  /// The view's index in CalibrationResult::views (the result file's `views`).
  std::optional<int> view;
  std::string text;  ///< the sentence for people

  bool operator==(const Warning& other) const;
  bool operator!=(const Warning& other) const { return !(*this == other); }
};

/// A warning about the run as a whole, one camera, or one robot pose.
Warning GeneralWarning(WarningKind kind, std::string text);
Warning CameraWarning(WarningKind kind, std::string camera, std::string text);
Warning PoseWarning(WarningKind kind, std::string pose, std::string text);

/// The sentences of `warnings`, in order.
std::vector<std::string> WarningTexts(const std::vector<Warning>& warnings);

}  // namespace handeye
