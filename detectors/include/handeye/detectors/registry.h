// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Target plugins keyed by `target.type`. A new target type is one geometry
/// class (core), one detector file pair and one RegisterTargetPlugin call;
/// built-in plugins are listed in registry.cc. Users may register their own
/// before loading a dataset.

#include <functional>
#include <memory>
#include <stdexcept>
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

/// The plugin of a target type whose geometry is `TargetT`, made from the
/// `target` object by `make_target`, and whose detector is `DetectorT`,
/// constructed from a std::shared_ptr<const TargetT>.
template <class TargetT, class DetectorT>
TargetPlugin MakeTargetPlugin(
    std::string type,
    std::function<std::shared_ptr<const TargetT>(const TargetSpec&)> make_target) {
  return {type,
          [make_target](const TargetSpec& spec) -> std::shared_ptr<const Target> {
            return make_target(spec);
          },
          [type](std::shared_ptr<const Target> target) -> std::unique_ptr<Detector> {
            auto typed = std::dynamic_pointer_cast<const TargetT>(std::move(target));
            if (!typed)
              throw std::invalid_argument("target plugin '" + type +
                                          "': the target was not made by this plugin");
            return std::make_unique<DetectorT>(std::move(typed));
          }};
}

/// The same, for a `TargetT` constructed from the `target` object itself.
template <class TargetT, class DetectorT>
TargetPlugin MakeTargetPlugin(std::string type) {
  return MakeTargetPlugin<TargetT, DetectorT>(
      std::move(type), [](const TargetSpec& spec) { return std::make_shared<const TargetT>(spec); });
}

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
