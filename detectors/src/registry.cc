// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/detectors/registry.h"

#include <algorithm>
#include <map>
#include <mutex>

#include "handeye/core/error.h"
#include "handeye/detectors/aprilgrid_detector.h"
#include "handeye/detectors/charuco_detector.h"
#include "handeye/detectors/checkerboard_detector.h"

namespace handeye {
namespace {

std::map<std::string, TargetPlugin> BuiltinPlugins() {
  std::map<std::string, TargetPlugin> plugins;
  auto add = [&plugins](TargetPlugin p) { plugins[p.type] = std::move(p); };
  // One line per built-in target type.
  add(MakeTargetPlugin<CheckerboardTarget, CheckerboardDetector>("checkerboard"));
  add(MakeTargetPlugin<CharucoTarget, CharucoDetector>("charuco", MakeCharucoTarget));
  add(MakeTargetPlugin<AprilGridTarget, AprilGridDetector>("aprilgrid", MakeAprilGridTarget));
  return plugins;
}

struct Registry {
  std::mutex mutex;
  std::map<std::string, TargetPlugin> plugins = BuiltinPlugins();
};

Registry& GetRegistry() {
  static Registry registry;
  return registry;
}

TargetPlugin FindPlugin(const std::string& type) {
  Registry& r = GetRegistry();
  std::lock_guard<std::mutex> lock(r.mutex);
  auto it = r.plugins.find(type);
  if (it != r.plugins.end()) return it->second;
  std::string known;
  for (const auto& [name, plugin] : r.plugins) known += (known.empty() ? "" : ", ") + name;
  throw InputError("", "/type",
                   "unknown target type '" + type + "'; expected one of: " + known);
}

}  // namespace

void RegisterTargetPlugin(TargetPlugin plugin) {
  Registry& r = GetRegistry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.plugins[plugin.type] = std::move(plugin);
}

std::vector<std::string> KnownTargetTypes() {
  Registry& r = GetRegistry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> types;
  for (const auto& [name, plugin] : r.plugins) types.push_back(name);
  return types;
}

std::shared_ptr<const Target> MakeTarget(const TargetSpec& spec) {
  return FindPlugin(spec.type).make_target(spec);
}

std::unique_ptr<Detector> MakeDetector(std::shared_ptr<const Target> target) {
  if (!target) throw std::invalid_argument("MakeDetector: null target");
  auto detector = FindPlugin(target->Type()).make_detector(target);
  if (!detector)
    throw std::invalid_argument("MakeDetector: plugin '" + target->Type() +
                                "' made no detector for this target");
  return detector;
}

}  // namespace handeye
