// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Target plugins keyed by `target.type`. A new target type is one geometry
/// class (core), one detector file pair and one RegisterTargetPlugin call;
/// built-in plugins are listed in registry.cc. Users may register their own
/// before loading a dataset.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "handeye/core/target.h"
#include "handeye/detectors/detector.h"

namespace handeye {

/// A target type: how to make its geometry and its detector. The functions
/// may be called from several threads at once.
struct TargetPlugin {
  std::string type;  ///< `target.type`
  /// Makes the geometry from the `target` object; throws InputError with the
  /// path of the offending key inside the object (e.g. `/dots`).
  std::function<std::shared_ptr<const Target>(const TargetSpec&)> make_target;
  /// Makes a detector for a target made by make_target (the registry passes
  /// that target back, so a cast to the plugin's own type is safe).
  std::function<std::unique_ptr<Detector>(std::shared_ptr<const Target>)> make_detector;
};

/// Adds a plugin, replacing one with the same type. Thread-safe.
void RegisterTargetPlugin(TargetPlugin plugin);
/// The registered target types, sorted.
std::vector<std::string> KnownTargetTypes();
/// Target for a spec; throws InputError at `/type` for an unknown type
/// (listing the known ones) or the plugin's own InputError.
std::shared_ptr<const Target> MakeTarget(const TargetSpec& spec);
/// Detector for a target made by MakeTarget.
std::unique_ptr<Detector> MakeDetector(std::shared_ptr<const Target> target);

}  // namespace handeye
