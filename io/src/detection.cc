// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/detection.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

#include "handeye/core/error.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/image.h"

namespace handeye {
namespace {

// One image to look at: where it is and which camera took it.
struct ImageTask {
  int pose = 0;
  int camera = 0;
  const std::string* path = nullptr;
};

}  // namespace

void DetectAll(Dataset* dataset, const DetectOptions& options) {
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

  unsigned threads = options.threads > 0 ? static_cast<unsigned>(options.threads)
                                         : std::max(1u, std::thread::hardware_concurrency());
  threads =
      static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(1, tasks.size())));

  std::atomic<std::size_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;  // guards first_error, done and the progress callback
  std::exception_ptr first_error;
  std::size_t done = 0;

  auto worker = [&]() {
    while (!stop.load()) {
      const std::size_t i = next.fetch_add(1);
      if (i >= tasks.size()) return;
      try {
        const ImageTask& task = tasks[i];
        // One image per worker in memory at a time: datasets may hold
        // thousands of full-resolution images.
        const cv::Mat gray = LoadGrayImage(*task.path, dataset->cameras[task.camera]);
        found[i] = detector->Detect(gray);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!first_error) first_error = std::current_exception();
        stop.store(true);
        return;
      }
      std::lock_guard<std::mutex> lock(mutex);
      ++done;
      if (options.progress && !stop.load()) options.progress(done, tasks.size());
    }
  };

  if (threads <= 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    pool.reserve(threads);
    for (unsigned t = 0; t < threads; ++t) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
  }
  if (first_error) std::rethrow_exception(first_error);

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
}

}  // namespace handeye
