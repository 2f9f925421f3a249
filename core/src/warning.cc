// SPDX-License-Identifier: GPL-2.0-or-later
// Warning kinds and their stable names (handeye/core/warning.h).

#include "handeye/core/warning.h"

#include <utility>

namespace handeye {
namespace {

struct KindName {
  WarningKind kind;
  const char* name;
};

// The names files carry: never rename one, only add.
constexpr KindName kKindNames[] = {
    {WarningKind::kOther, "other"},
    {WarningKind::kTargetAmbiguous, "target_ambiguous"},
    {WarningKind::kTargetMismatch, "target_mismatch"},
    {WarningKind::kRepeatedImages, "repeated_images"},
    {WarningKind::kPoseFilesDisagree, "pose_files_disagree"},
    {WarningKind::kCameraNotSeen, "camera_not_seen"},
    {WarningKind::kCameraNoUsableViews, "camera_no_usable_views"},
    {WarningKind::kCameraMethodFailed, "camera_method_failed"},
    {WarningKind::kViewLeftOut, "view_left_out"},
    {WarningKind::kObliqueViewsLeftOut, "oblique_views_left_out"},
    {WarningKind::kPoseRecordMismatch, "pose_record_mismatch"},
    {WarningKind::kManyViewsOff, "many_views_off"},
    {WarningKind::kNotConverged, "not_converged"},
    {WarningKind::kIntrinsicsUndetermined, "intrinsics_undetermined"},
    {WarningKind::kIntrinsicsOff, "intrinsics_off"},
    {WarningKind::kFewViews, "few_views"},
    {WarningKind::kPoorRotationSpread, "poor_rotation_spread"},
    {WarningKind::kPoorRotationAxes, "poor_rotation_axes"},
    {WarningKind::kLargeResiduals, "large_residuals"},
    {WarningKind::kOutlierViews, "outlier_views"},
    {WarningKind::kClosedFormDisagrees, "closed_form_disagrees"},
    {WarningKind::kDriftNotChecked, "drift_not_checked"},
    {WarningKind::kDriftWithinNoise, "drift_within_noise"},
    {WarningKind::kDriftTooCoarse, "drift_too_coarse"},
    {WarningKind::kCameraNotExported, "camera_not_exported"},
    {WarningKind::kResultViewsMissing, "result_views_missing"},
};

}  // namespace

const char* WarningKindName(WarningKind kind) {
  for (const KindName& k : kKindNames)
    if (k.kind == kind) return k.name;
  return "other";
}

std::optional<WarningKind> ParseWarningKind(const std::string& name) {
  for (const KindName& k : kKindNames)
    if (name == k.name) return k.kind;
  return std::nullopt;
}

bool Warning::operator==(const Warning& other) const {
  return kind == other.kind && camera == other.camera && pose == other.pose && view == other.view &&
         text == other.text;
}

Warning GeneralWarning(WarningKind kind, std::string text) {
  Warning w;
  w.kind = kind;
  w.text = std::move(text);
  return w;
}

Warning CameraWarning(WarningKind kind, std::string camera, std::string text) {
  Warning w = GeneralWarning(kind, std::move(text));
  w.camera = std::move(camera);
  return w;
}

Warning PoseWarning(WarningKind kind, std::string pose, std::string text) {
  Warning w = GeneralWarning(kind, std::move(text));
  w.pose = std::move(pose);
  return w;
}

std::vector<std::string> WarningTexts(const std::vector<Warning>& warnings) {
  std::vector<std::string> texts;
  texts.reserve(warnings.size());
  for (const Warning& w : warnings) texts.push_back(w.text);
  return texts;
}

}  // namespace handeye
