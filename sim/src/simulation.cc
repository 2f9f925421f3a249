// SPDX-License-Identifier: GPL-2.0-or-later
// Writes a simulated dataset: one rendered PNG per view that counts, then the
// dataset and its ground truth. Views are rendered by a pool of threads, each
// holding one image in memory at a time; every image has its own seed derived
// from the render seed and the view, so the output does not depend on the
// number of threads.

#include "handeye/sim/simulation.h"

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "handeye/core/error.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/image.h"
#include "parallel.h"

namespace handeye {
namespace {

namespace fs = std::filesystem;

/// SplitMix64's finaliser: spreads nearby inputs (view indices) over all 64 bits.
std::uint64_t Mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// Real lenses differ in sharpness: camera k's blur is the requested σ times
/// a factor in [2/3, 4/3] fixed by the seed (so 0.75 px gives 0.5–1.0 px).
double CameraBlur(double mean_sigma_px, std::uint64_t seed, std::size_t camera) {
  const double unit = static_cast<double>(Mix(seed ^ Mix(0xb1u + camera)) >> 11) * 0x1.0p-53;
  return mean_sigma_px * (2.0 / 3.0 + unit * 2.0 / 3.0);
}

struct View {
  std::size_t pose = 0;
  std::size_t camera = 0;
};

/// The views to render, in pose then camera order: every camera at every pose
/// (as a real capture), or only those the truth counts as seeing the target.
std::vector<View> ViewsToRender(const SyntheticScene& scene, const RenderOptions& render) {
  std::vector<View> views;
  for (std::size_t j = 0; j < scene.truth.poses.size(); ++j)
    for (std::size_t k = 0; k < scene.dataset.cameras.size(); ++k)
      if (render.every_view || scene.truth.poses[j].points_px.count(scene.dataset.cameras[k].name))
        views.push_back({j, k});
  return views;
}

/// Renders the views on a pool of threads, one image per thread in memory,
/// and hands each to `sink(view index, image)` (called concurrently). Each
/// image has its own seed derived from the render seed and the view, so the
/// output does not depend on the thread count. The first exception stops the
/// pool and is rethrown.
void RenderViews(const SyntheticScene& scene, const std::vector<View>& views, const RenderOptions& render,
                 int threads, const std::function<void(std::size_t, const cv::Mat&)>& sink,
                 const std::function<void(std::size_t, std::size_t)>& progress) {
  std::string why;
  if (!render.Check(&why)) throw std::invalid_argument("bad render options: " + why);
  if (!scene.dataset.target) throw std::invalid_argument("scene without a target");
  if (scene.truth.poses.size() != scene.dataset.poses.size())
    throw std::invalid_argument("scene truth does not match its poses");
  internal::ParallelFor(
      views.size(), threads,
      [&](std::size_t i) {
        const View& view = views[i];
        RenderOptions options = render;
        options.seed = Mix(render.seed ^ Mix(view.pose * 0x10001u + view.camera));
        options.blur_sigma_px = CameraBlur(render.blur_sigma_px, render.seed, view.camera);
        const auto own = render.camera_quality.find(scene.dataset.cameras[view.camera].name);
        if (own != render.camera_quality.end()) {
          options.blur_sigma_px = own->second.blur_sigma_px;
          options.noise_sigma = own->second.noise_sigma;
        }
        sink(i, RenderView(scene.dataset.cameras[view.camera], *scene.dataset.target,
                           TrueCameraFromTarget(scene, static_cast<int>(view.camera),
                                                static_cast<int>(view.pose)),
                           options));
      },
      progress);
}

}  // namespace

void WriteSimulation(SyntheticScene* scene, const RenderOptions& render, const std::string& outdir,
                     int threads, const std::function<void(std::size_t, std::size_t)>& progress) {
  Dataset& dataset = scene->dataset;
  // Absolute paths, so the dataset writer can make them relative to its file
  // whatever the working directory.
  const fs::path root = fs::absolute(fs::path(outdir)).lexically_normal();
  const std::vector<View> views = ViewsToRender(*scene, render);
  std::vector<std::string> paths;
  for (auto& pose : dataset.poses) pose.images.clear();
  for (const View& view : views) {
    const std::string& name = dataset.cameras[view.camera].name;
    paths.push_back((root / "images" / name / (dataset.poses[view.pose].id + ".png")).string());
    dataset.poses[view.pose].images[name] = paths.back();
  }
  for (const Camera& camera : dataset.cameras) {
    std::error_code ec;
    fs::create_directories(root / "images" / camera.name, ec);
    if (ec) throw InputError((root / "images" / camera.name).string(), "",
                             "cannot create the folder: " + ec.message());
  }
  RenderViews(*scene, views, render, threads,
              [&](std::size_t i, const cv::Mat& image) { WritePng(paths[i], image); }, progress);
  SaveDataset(dataset, (root / "dataset.json").string());
  SaveGroundTruth(scene->truth, (root / "ground_truth.json").string());
}

void DetectSimulated(SyntheticScene* scene, const RenderOptions& render, int threads,
                     const std::function<void(std::size_t, std::size_t)>& progress) {
  Dataset& dataset = scene->dataset;
  const std::vector<View> views = ViewsToRender(*scene, render);
  const std::unique_ptr<Detector> detector = MakeDetector(dataset.target);
  std::vector<std::optional<Observation>> found(views.size());
  RenderViews(*scene, views, render, threads,
              [&](std::size_t i, const cv::Mat& image) {
                const auto detection = detector->Detect(image);
                if (!detection) return;
                Observation obs;
                obs.pose_id = dataset.poses[views[i].pose].id;
                obs.camera = dataset.cameras[views[i].camera].name;
                obs.ids = detection->ids;
                obs.points_px = detection->points_px;
                found[i] = std::move(obs);  // each slot written by one thread only
              },
              progress);
  dataset.observations.clear();
  for (auto& obs : found)
    if (obs) dataset.observations.push_back(std::move(*obs));
}

}  // namespace handeye
