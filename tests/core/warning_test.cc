// SPDX-License-Identifier: GPL-2.0-or-later
// Warning kinds: stable names that files carry and read back.
#include <catch2/catch.hpp>

#include <set>
#include <string>

#include "handeye/core/warning.h"

using namespace handeye;

TEST_CASE("Warning kind names are snake_case, distinct and read back", "[warning]") {
  std::set<std::string> names;
  // kResultViewsMissing is the last kind (warning.h).
  for (int k = 0; k <= static_cast<int>(WarningKind::kResultViewsMissing); ++k) {
    const WarningKind kind = static_cast<WarningKind>(k);
    const std::string name = WarningKindName(kind);
    INFO(k << ": " << name);
    CHECK(names.insert(name).second);
    CHECK(name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") == std::string::npos);
    const auto back = ParseWarningKind(name);
    REQUIRE(back);
    CHECK(*back == kind);
  }
  // Names files already carry keep their meaning.
  CHECK(std::string(WarningKindName(WarningKind::kViewLeftOut)) == "view_left_out");
  CHECK(std::string(WarningKindName(WarningKind::kCameraNotSeen)) == "camera_not_seen");
  CHECK_FALSE(ParseWarningKind("View_Left_Out"));
  CHECK_FALSE(ParseWarningKind(""));
}

TEST_CASE("Warnings say what they are about, and their texts keep their order", "[warning]") {
  const Warning general = GeneralWarning(WarningKind::kNotConverged, "stopped");
  CHECK(general.camera.empty());
  CHECK(general.pose.empty());
  CHECK_FALSE(general.view);
  const Warning camera = CameraWarning(WarningKind::kFewViews, "cam1", "few");
  CHECK(camera.camera == "cam1");
  const Warning pose = PoseWarning(WarningKind::kPoseRecordMismatch, "0007", "off");
  CHECK(pose.pose == "0007");
  CHECK(pose.camera.empty());
  CHECK(WarningTexts({general, camera, pose}) == std::vector<std::string>{"stopped", "few", "off"});
  CHECK(camera != CameraWarning(WarningKind::kFewViews, "cam2", "few"));
  CHECK(camera == CameraWarning(WarningKind::kFewViews, "cam1", "few"));
}
