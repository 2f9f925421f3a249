// SPDX-License-Identifier: GPL-2.0-or-later
// Detection time per image for each target type, on the views of a rendered
// workcell (the cell's cameras, lens distortion, clutter, blur and noise),
// with what was found against the ground truth.
//
//   bench_detect_targets --targets checkerboard,charuco,aprilgrid --cell medium --poses 20
//
// With --by-angle N: recall by view angle instead, N views per angle bucket
// of each target, the whole sheet in view of one of the cell's cameras at
// the cell's distances, with blur, noise and clutter drawn per view.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

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

/// Counts the points of `detection` found (within 3 px of their true pixels
/// `true_px`, by id) and wrong, with the error of each one found.
void Tally(const Detection& detection, const std::map<int, Eigen::Vector2d>& true_px, int* found,
           int* wrong, std::vector<double>* errors) {
  for (std::size_t i = 0; i < detection.ids.size(); ++i) {
    const auto it = true_px.find(detection.ids[i]);
    const double error = it == true_px.end() ? 1e9 : (detection.points_px[i] - it->second).norm();
    if (error > 3.0) {
      ++*wrong;
      continue;
    }
    ++*found;
    errors->push_back(error);
  }
}

/// Angle between the sheet's normal and the line of sight to its centre (deg).
double ViewAngleDeg(const Target& target, const Eigen::Isometry3d& T_cam_target) {
  const Eigen::Vector2d c = target.Extent().center();
  const Eigen::Vector3d centre_cam = T_cam_target * Eigen::Vector3d(c.x(), c.y(), 0.0);
  const Eigen::Vector3d normal_cam = T_cam_target.linear().col(2);
  return std::acos(std::min(1.0, std::abs(normal_cam.dot(centre_cam.normalized())))) * 180.0 / M_PI;
}

/// True when the whole sheet projects at least `margin` px inside the image.
bool SheetInView(const Camera& camera, const Target& target, const Eigen::Isometry3d& T_cam_target,
                 double margin) {
  const Eigen::AlignedBox2d e = target.Extent();
  for (int k = 0; k <= 20; ++k) {
    const double s = k / 20.0;
    for (const Eigen::Vector2d& p :
         {Eigen::Vector2d(e.min().x() + s * e.sizes().x(), e.min().y()),
          Eigen::Vector2d(e.min().x() + s * e.sizes().x(), e.max().y()),
          Eigen::Vector2d(e.min().x(), e.min().y() + s * e.sizes().y()),
          Eigen::Vector2d(e.max().x(), e.min().y() + s * e.sizes().y())}) {
      const auto uv = camera.Project(T_cam_target * Eigen::Vector3d(p.x(), p.y(), 0.0));
      if (!uv || !camera.InImage(*uv, margin)) return false;
    }
  }
  return true;
}

/// A view of the whole sheet from `camera` at `distance_m` whose view angle
/// is in [lo_deg, hi_deg): turned about its normal and tilted about an
/// in-plane axis at random, centred on the ray through a random pixel of the
/// image's middle. nullopt when 200 draws found none.
std::optional<Eigen::Isometry3d> ViewInBucket(const Camera& camera, const Target& target,
                                              double distance_m, double lo_deg, double hi_deg,
                                              std::mt19937_64* rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int attempt = 0; attempt < 200; ++attempt) {
    const double tilt = (lo_deg + (hi_deg - lo_deg) * unit(*rng)) * M_PI / 180.0;
    const double spin = 2 * M_PI * unit(*rng), axis_angle = 2 * M_PI * unit(*rng);
    const Eigen::Vector3d axis(std::cos(axis_angle), std::sin(axis_angle), 0.0);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = (Eigen::AngleAxisd(tilt, axis) * Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()))
                     .toRotationMatrix();
    const double u = (0.2 + 0.6 * unit(*rng)) * camera.width;
    const double v = (0.2 + 0.6 * unit(*rng)) * camera.height;
    const Eigen::Vector3d ray((u - camera.cx()) / camera.fx(), (v - camera.cy()) / camera.fy(), 1.0);
    const Eigen::Vector2d c = target.Extent().center();
    T.translation() = distance_m * ray.normalized() - T.linear() * Eigen::Vector3d(c.x(), c.y(), 0.0);
    const double angle = ViewAngleDeg(target, T);
    if (angle >= lo_deg && angle < hi_deg && SheetInView(camera, target, T, 8.0)) return T;
  }
  return std::nullopt;
}

/// Recall by view angle: one row per target and angle bucket.
int RecallByAngle(const std::vector<std::string>& types, const SceneOptions& cell, int views) {
  const std::vector<std::pair<double, double>> buckets = {
      {0, 45}, {45, 60}, {60, 70}, {70, 75}, {75, 80}};
  Table table({"target", "view angle", "views", "views found", "points in view", "points found",
               "wrong ids", "mean error px", "max error px", "detect ms mean"});
  for (const std::string& type : types) {
    const auto target = MakeTarget(DefaultSpec(type));
    const auto detector = MakeDetector(target);
    const SyntheticScene scene = MakeScene(cell, target);
    // The cell's distances from camera to sheet.
    std::vector<double> distances;
    for (std::size_t j = 0; j < scene.truth.poses.size(); ++j)
      for (std::size_t k = 0; k < scene.dataset.cameras.size(); ++k)
        distances.push_back(
            TrueCameraFromTarget(scene, static_cast<int>(k), static_cast<int>(j)).translation().norm());
    for (std::size_t b = 0; b < buckets.size(); ++b) {
      std::mt19937_64 rng(cell.seed * 7919 + b);
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      int drawn = 0, found_views = 0, in_view = 0, found = 0, wrong = 0;
      std::vector<double> errors, times_ms;
      for (int n = 0; n < views; ++n) {
        const std::size_t k = rng() % scene.dataset.cameras.size();
        const Camera& camera = scene.dataset.cameras[k];
        const double distance = distances[rng() % distances.size()];
        const auto T_cam_target =
            ViewInBucket(camera, *target, distance, buckets[b].first, buckets[b].second, &rng);
        if (!T_cam_target) continue;
        RenderOptions render;
        render.blur_sigma_px = 0.6 + 0.6 * unit(rng);
        render.noise_sigma = 2.0 + 4.0 * unit(rng);
        render.seed = rng();
        const cv::Mat image = RenderView(camera, *target, *T_cam_target, render);
        ++drawn;
        std::map<int, Eigen::Vector2d> true_px;
        for (const TargetPoint& p : target->Points()) {
          const auto uv = camera.Project(*T_cam_target * p.p_target);
          if (uv && camera.InImage(*uv, 4.0)) true_px[p.id] = *uv;
        }
        in_view += static_cast<int>(true_px.size());
        const Stopwatch watch;
        const auto detection = detector->Detect(image);
        times_ms.push_back(1000.0 * watch.Seconds());
        if (!detection) continue;
        ++found_views;
        Tally(*detection, true_px, &found, &wrong, &errors);
      }
      double max_error = 0;
      for (double e : errors) max_error = std::max(max_error, e);
      table.Add({type, Format("%.0f-%.0f", buckets[b].first, buckets[b].second),
                 Format("%d", drawn), Format("%d", found_views), Format("%d", in_view),
                 Format("%d (%.1f %%)", found, in_view ? 100.0 * found / in_view : 0.0),
                 Format("%d", wrong), Format("%.3f", Mean(errors)), Format("%.3f", max_error),
                 Format("%.1f", Mean(times_ms))});
      std::fprintf(stderr, "%s %.0f-%.0f done\n", type.c_str(), buckets[b].first,
                   buckets[b].second);
    }
  }
  std::printf(
      "Recall by view angle (angle between the sheet's normal and the line of sight to its\n"
      "centre) on rendered %s-cell views, %dx%d: the whole sheet in view of one of the\n"
      "cell's cameras at one of its distances, blur sigma 0.6-1.2 px, noise sigma 2-6 grey\n"
      "levels, clutter; a found point more than 3 px from its truth is a wrong id\n\n%s",
      cell.cell.c_str(), cell.width, cell.height, table.Markdown().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"handeye target detection benchmark: time per image and what was found"};
  std::string targets = "checkerboard,charuco,aprilgrid", cell = "medium", size = "1920x1080";
  int cameras = 4, poses = 20;
  std::uint64_t seed = 1;
  int by_angle = 0;
  app.add_option("--by-angle", by_angle,
                 "views per view-angle bucket: recall by angle instead of the cell's views");
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
  SceneOptions options;
  options.cell = cell;
  options.num_cameras = cameras;
  options.num_poses = poses;
  options.seed = seed;
  options.width = width;
  options.height = height;
  if (by_angle > 0) return RecallByAngle(SplitList(targets), options, by_angle);

  Table table({"target", "views", "detected", "true points", "found", "wrong (> 3 px)",
               "mean error px", "max error px", "detect ms median", "detect ms mean", "detect ms max"});
  for (const std::string& type : SplitList(targets)) {
    const auto target = MakeTarget(DefaultSpec(type));
    const auto detector = MakeDetector(target);
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
        const Eigen::Isometry3d T_cam_target =
            TrueCameraFromTarget(scene, static_cast<int>(k), static_cast<int>(j));
        const cv::Mat image = RenderView(camera, *target, T_cam_target, render);
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
        // A point the scene does not count (seen beyond its angle limit, or
        // near the border) is still wrong only when found off its projection.
        for (const TargetPoint& p : target->Points())
          if (const auto uv = camera.Project(T_cam_target * p.p_target); uv && !true_px.count(p.id))
            true_px[p.id] = *uv;
        Tally(*detection, true_px, &found, &wrong, &errors);
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
