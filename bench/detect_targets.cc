// SPDX-License-Identifier: GPL-2.0-or-later
// Detection time per image for each target type, on the views of a rendered
// workcell (the cell's cameras, lens distortion, clutter, blur and noise),
// with what was found against the ground truth.
//
//   bench_detect_targets --targets checkerboard,charuco,aprilgrid --cell medium --poses 20
#include <CLI/CLI.hpp>
#include <cstdio>
#include <map>

#include "handeye/detectors/registry.h"
#include "handeye/sim/render.h"
#include "handeye/sim/synthetic.h"
#include "support/bench_support.h"

using namespace handeye;
using namespace handeye::bench;

namespace {

/// The sheets `handeye simulate --target TYPE` renders by default.
TargetSpec DefaultSpec(const std::string& type) {
  TargetSpec spec;
  spec.type = type;
  if (type == "checkerboard") {
    spec.values["inner_corners"] = std::vector<double>{7, 4};
    spec.values["square_size_m"] = 0.04;
  } else if (type == "charuco") {
    spec.values["squares"] = std::vector<double>{7, 5};
    spec.values["square_size_m"] = 0.055;
    spec.values["marker_size_m"] = 0.04;
    spec.values["dictionary"] = std::string("DICT_5X5_100");
  } else if (type == "aprilgrid") {
    spec.values["tags"] = std::vector<double>{6, 4};
    spec.values["tag_size_m"] = 0.05;
    spec.values["tag_spacing"] = 0.25;
  }
  return spec;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"handeye target detection benchmark: time per image and what was found"};
  std::string targets = "checkerboard,charuco,aprilgrid", cell = "medium", size = "1920x1080";
  int cameras = 4, poses = 20;
  std::uint64_t seed = 1;
  app.add_option("--targets", targets, "comma-separated target types (their default sheets)");
  app.add_option("--cell", cell, "small, medium or large");
  app.add_option("--cameras", cameras, "cameras in the cell");
  app.add_option("--poses", poses, "robot poses");
  app.add_option("--image-size", size, "WIDTHxHEIGHT");
  app.add_option("--seed", seed, "scene seed");
  CLI11_PARSE(app, argc, argv);
  int width = 0, height = 0;
  if (std::sscanf(size.c_str(), "%dx%d", &width, &height) != 2) {
    std::fprintf(stderr, "--image-size: expected WIDTHxHEIGHT\n");
    return 2;
  }

  Table table({"target", "views", "detected", "true points", "found", "wrong (> 3 px)",
               "mean error px", "max error px", "detect ms median", "detect ms mean", "detect ms max"});
  for (const std::string& type : SplitList(targets)) {
    const auto target = MakeTarget(DefaultSpec(type));
    const auto detector = MakeDetector(target);
    SceneOptions options;
    options.cell = cell;
    options.num_cameras = cameras;
    options.num_poses = poses;
    options.seed = seed;
    options.width = width;
    options.height = height;
    const SyntheticScene scene = MakeScene(options, target);
    std::vector<double> times_ms, errors;
    int views = 0, detected = 0, truth_points = 0, found = 0, wrong = 0;
    for (std::size_t j = 0; j < scene.truth.poses.size(); ++j) {
      for (std::size_t k = 0; k < scene.dataset.cameras.size(); ++k) {
        const Camera& camera = scene.dataset.cameras[k];
        const auto truth = scene.truth.poses[j].points_px.find(camera.name);
        if (truth == scene.truth.poses[j].points_px.end()) continue;
        RenderOptions render;
        render.blur_sigma_px = 0.75;
        render.seed = seed * 100000 + j * 100 + k;
        const cv::Mat image = RenderView(
            camera, *target, TrueCameraFromTarget(scene, static_cast<int>(k), static_cast<int>(j)),
            render);
        const Stopwatch watch;
        const auto detection = detector->Detect(image);
        times_ms.push_back(1000.0 * watch.Seconds());
        ++views;
        truth_points += static_cast<int>(truth->second.ids.size());
        if (!detection) continue;
        ++detected;
        std::map<int, Eigen::Vector2d> true_px;
        for (std::size_t i = 0; i < truth->second.ids.size(); ++i)
          true_px[truth->second.ids[i]] = truth->second.points_px[i];
        for (std::size_t i = 0; i < detection->ids.size(); ++i) {
          const auto it = true_px.find(detection->ids[i]);
          const double error =
              it == true_px.end() ? 1e9 : (detection->points_px[i] - it->second).norm();
          if (error > 3.0) {
            ++wrong;
            continue;
          }
          ++found;
          errors.push_back(error);
        }
      }
    }
    double max_ms = 0, max_error = 0;
    for (double t : times_ms) max_ms = std::max(max_ms, t);
    for (double e : errors) max_error = std::max(max_error, e);
    table.Add({type, Format("%d", views), Format("%d", detected), Format("%d", truth_points),
               Format("%d (%.1f %%)", found, truth_points ? 100.0 * found / truth_points : 0.0),
               Format("%d", wrong), Format("%.3f", Mean(errors)), Format("%.3f", max_error),
               Format("%.1f", Median(times_ms)),
               Format("%.1f", Mean(times_ms)), Format("%.1f", max_ms)});
    std::fprintf(stderr, "%s done\n", type.c_str());
  }
  std::printf(
      "Detection on rendered %s-cell views, %dx%d, one thread per image (true points: all\n"
      "points projected inside the image, whether their fiducial is whole or not)\n\n%s",
      cell.c_str(), width, height, table.Markdown().c_str());
  return 0;
}
