// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/detection.h"

#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>
#include <vector>

#include "handeye/core/error.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/image.h"
#include "parallel.h"

namespace handeye {
namespace {

// One image to look at: where it is and which camera took it.
struct ImageTask {
  int pose = 0;
  int camera = 0;
  const std::string* path = nullptr;
};

/// One warning per distinct declaration mismatch, with how many of the
/// `not_found` images without a detection showed it.
std::vector<Warning> MismatchWarnings(const std::vector<std::string>& mismatch, std::size_t not_found) {
  std::map<std::string, std::size_t> images;
  for (const std::string& m : mismatch)
    if (!m.empty()) ++images[m];
  std::vector<Warning> warnings;
  for (const auto& [m, count] : images)
    warnings.push_back(GeneralWarning(WarningKind::kTargetMismatch,
                       "target: " + m + " (seen in " + std::to_string(count) + " of the " +
                       std::to_string(not_found) + " images where the target was not found)"));
  return warnings;
}

}  // namespace

std::vector<Warning> DetectAll(Dataset* dataset, const DetectOptions& options) {
  if (!dataset) throw std::invalid_argument("DetectAll: null dataset");
  if (!dataset->target) throw std::invalid_argument("DetectAll: dataset without a target");
  if (options.threads < 0)
    throw std::invalid_argument("DetectAll: threads must be >= 0 (0 = all cores)");

  // Pose then camera order (the dataset's camera order), which is also the
  // order of the observations written below, whatever order workers finish in.
  std::vector<ImageTask> tasks;
  for (std::size_t p = 0; p < dataset->poses.size(); ++p) {
    const RobotPose& pose = dataset->poses[p];
    for (std::size_t c = 0; c < dataset->cameras.size(); ++c) {
      auto it = pose.images.find(dataset->cameras[c].name);
      if (it != pose.images.end())
        tasks.push_back({static_cast<int>(p), static_cast<int>(c), &it->second});
    }
    for (const auto& [camera, image] : pose.images)
      if (dataset->CameraIndex(camera) < 0)
        throw InputError(image, "",
                         "image of pose '" + pose.id + "' names unknown camera '" + camera + "'");
  }

  const std::unique_ptr<Detector> detector = MakeDetector(dataset->target);
  std::vector<std::optional<Detection>> found(tasks.size());
  std::vector<std::string> mismatch(tasks.size());

  // One image per worker in memory at a time: datasets may hold thousands of
  // full-resolution images.
  internal::ParallelFor(
      tasks.size(), options.threads,
      [&](std::size_t i) {
        const ImageTask& task = tasks[i];
        found[i] = detector->DetectOrExplain(
            LoadGrayImage(*task.path, dataset->cameras[task.camera]), &mismatch[i]);
      },
      options.progress);

  dataset->observations.clear();
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    // An empty detection is "not found": the observation format has no entry then.
    if (!found[i] || found[i]->ids.empty()) continue;
    Observation view;
    view.pose_id = dataset->poses[tasks[i].pose].id;
    view.camera = dataset->cameras[tasks[i].camera].name;
    view.ids = std::move(found[i]->ids);
    view.points_px = std::move(found[i]->points_px);
    if (view.points_px.size() != view.ids.size())
      throw std::logic_error("detector returned " + std::to_string(view.ids.size()) + " ids but " +
                             std::to_string(view.points_px.size()) + " points for " +
                             *tasks[i].path);
    dataset->observations.push_back(std::move(view));
  }
  return MismatchWarnings(mismatch, tasks.size() - dataset->observations.size());
}

}  // namespace handeye
