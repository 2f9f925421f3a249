// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/dataset.h"

namespace handeye {

const char* SetupName(Setup setup) {
  return setup == Setup::kEyeToHand ? "eye_to_hand" : "eye_in_hand";
}

std::optional<Setup> ParseSetup(const std::string& name) {
  if (name == "eye_to_hand") return Setup::kEyeToHand;
  if (name == "eye_in_hand") return Setup::kEyeInHand;
  return std::nullopt;
}

int Dataset::CameraIndex(const std::string& name) const {
  for (size_t i = 0; i < cameras.size(); ++i)
    if (cameras[i].name == name) return static_cast<int>(i);
  return -1;
}

int Dataset::PoseIndex(const std::string& id) const {
  for (size_t i = 0; i < poses.size(); ++i)
    if (poses[i].id == id) return static_cast<int>(i);
  return -1;
}

}  // namespace handeye
