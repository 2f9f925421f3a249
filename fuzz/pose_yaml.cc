// SPDX-License-Identifier: GPL-2.0-or-later
// ReadPoseYaml: a YAML list of ROS geometry_msgs/Pose (or a PoseArray, or
// PoseStamped items) for `handeye import-poses`.
#include "fuzz_support.h"
#include "handeye/io/pose_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = handeye::fuzz::InputFile("poses.yaml", data, size);
  handeye::PoseListOptions options;
  options.unit = size % 2 ? handeye::LengthUnit::kMillimetre : handeye::LengthUnit::kMetre;
  options.reorthonormalise = size % 3 == 0;
  handeye::fuzz::ExpectInputErrorsOnly([&] {
    const auto rows = handeye::ReadPoseList(path, options);
    handeye::RequirePlausibleReach(rows, path, options.unit, "--translation-unit");
  });
  return 0;
}
