// SPDX-License-Identifier: GPL-2.0-or-later
// Is the σ in the result honest? Over simulated cells, detection noise and
// robot pose error, the fraction of cameras whose true position (rotation)
// error lies within 2σ of the estimate. Honest: 85–98 %; lower is
// overconfident, higher uselessly wide. Projected observations (true pixels
// plus Gaussian noise of --noise px), or --source images: the views that
// show the target rendered (blur, sensor noise of --noise grey levels,
// clutter, oblique boards) and detected.
//
//   bench_uncertainty --cells small,medium,large --robot 0/0,0.1/0.01,0.3/0.03
//       --noise 0.1,0.3 --seeds 6 --poses 20   (one line)
//   bench_uncertainty --source images --noise 2,6 --image-size 1280x720 ...
//   bench_uncertainty --source images --intrinsics-off 0/0,1/3   (given intrinsics 1 %, 3 px off)
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/transform.h"
#include "handeye/sim/render.h"
#include "handeye/sim/simulation.h"
#include "handeye/sim/synthetic.h"
#include "support/bench_support.h"

using namespace handeye;
using namespace handeye::bench;

int main(int argc, char** argv) {
  CLI::App app{"handeye: coverage of the result's 1σ against the truth"};
  std::string cells = "small,medium,large", robot = "0/0,0.1/0.01,0.3/0.03", noise = "0.1,0.3";
  std::string source = "projected", image_size, intrinsics_off = "0/0", intrinsics_sigma;
  int seeds = 6, poses = 20, threads = 0, first_seed = 1001, cameras_per_cell = 4;
  bool given_robot_sigma = false;
  app.add_option("--cells", cells, "cells");
  app.add_option("--robot", robot, "robot pose error σ, MM/DEG per axis, comma-separated");
  app.add_option("--source", source, "projected (true pixels + noise) or images (rendered and detected)")
      ->check(CLI::IsMember({"projected", "images"}));
  app.add_option("--noise", noise,
                 "projected: detection noise σ per image axis (px); images: sensor noise σ (grey levels); "
                 "comma-separated");
  app.add_option("--image-size", image_size, "images: WIDTHxHEIGHT (default: the cell's 1920x1080)");
  app.add_option("--threads", threads, "images: render/detect threads (0 = all cores)");
  app.add_option("--seeds", seeds, "scenes per combination");
  app.add_option("--poses", poses, "robot poses per scene");
  app.add_option("--cameras", cameras_per_cell, "cameras per scene");
  app.add_option("--first-seed", first_seed,
                 "seed of the first scene of each combination (default 1001)");
  app.add_option(
      "--intrinsics-off", intrinsics_off,
      "images: the given intrinsics off by PCT % in focal length and PX in the principal point "
      "(even cameras +, odd −), PCT/PX comma-separated; the detections use the true ones");
  app.add_option("--intrinsics-sigma", intrinsics_sigma,
                 "the solver's --intrinsics-sigma (default: the library's; 0: the given intrinsics exact)");
  app.add_flag("--given-robot-sigma", given_robot_sigma,
               "give the solver the simulated robot σ instead of letting it estimate it");
  CLI11_PARSE(app, argc, argv);

  if (source != "images" && intrinsics_off != "0/0") {
    std::fprintf(stderr, "--intrinsics-off: with --source images only\n");
    return 2;
  }
  Table table({"cell", "robot σ", source == "images" ? "noise grey" : "noise px", "intrinsics off",
               "cameras", "views", "e_t ≤ 2σ", "e_θ ≤ 2σ", "e_t, e_θ > 3σ", "median e_t/σ", "max e_t/σ",
               "max e_θ/σ", "mean σ mm", "mean e_t mm", "modelled robot σ"});
  int all_cameras = 0, all_t = 0, all_r = 0, scenes = 0;
  for (const std::string& cell : SplitList(cells))
    for (const std::string& r : SplitList(robot))
      for (const std::string& n : SplitList(noise))
        for (const std::string& off : SplitList(intrinsics_off)) {
          const auto slash = r.find('/');
          const double robot_mm = std::stod(r.substr(0, slash)),
                       robot_deg = std::stod(r.substr(slash + 1));
          const double noise = std::stod(n);
          SceneOptions options;
          options.cell = cell;
          options.num_cameras = cameras_per_cell;
          options.num_poses = poses;
          options.pose_noise_mm = robot_mm;
          options.pose_noise_deg = robot_deg;
          if (!image_size.empty() &&
              std::sscanf(image_size.c_str(), "%dx%d", &options.width, &options.height) != 2) {
            std::fprintf(stderr, "--image-size: expected WIDTHxHEIGHT\n");
            return 2;
          }
          CalibrationOptions calibration;
          if (!intrinsics_sigma.empty()) {
            std::string why;
            const auto sigma = ParseIntrinsicsSigma(intrinsics_sigma, &why);
            if (!sigma) {
              std::fprintf(stderr, "--intrinsics-sigma: %s\n", why.c_str());
              return 2;
            }
            calibration.intrinsics_sigma = *sigma;
          }
          if (given_robot_sigma && robot_mm > 0) {
            calibration.robot_sigma_mm = robot_mm;
            // The simulator's turn of N(0, robot_deg) about a random axis.
            calibration.robot_sigma_deg = robot_deg / std::sqrt(3.0);
          }
          SigmaCoverage c;
          // Per camera with a σ: its views and its rotation error over σ (the
          // coverage holds the position's), for the extremes of the table.
          int fewest_views = 0, most_views = 0;
          std::vector<double> rotation_ratio;
          if (source == "projected") {
            c = MeasureSigmaCoverage(options, noise, seeds, first_seed, calibration);
          } else {
            for (int i = 0; i < seeds; ++i) {
              options.seed = first_seed + i;
              SyntheticScene scene =
                  MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
              RenderOptions render;
              render.seed = options.seed * 1000003u;
              render.noise_sigma = noise;
              // Only the views that show the target: the others are found empty
              // and add nothing to σ, and rendering them tripled a scene's time.
              render.every_view = false;
              DetectSimulated(&scene, render, threads);
              IntrinsicsOffset offset;
              if (!ParseIntrinsicsOffset(off, &offset)) {
                std::fprintf(stderr, "--intrinsics-off: PCT/PX, e.g. 1/3, got '%s'\n", off.c_str());
                return 2;
              }
              OffsetIntrinsics(offset, &scene.dataset);
              try {
                const CalibrationResult result = Calibrate(scene.dataset, calibration);
                AddToCoverage(result, scene.truth, &c);
                for (const CameraResult& camera : result.cameras) {
                  if (!camera.calibrated || !camera.sigma) continue;
                  fewest_views = fewest_views ? std::min(fewest_views, camera.views) : camera.views;
                  most_views = std::max(most_views, camera.views);
                  const Eigen::Isometry3d& T = scene.truth.T_cam.at(camera.name);
                  rotation_ratio.push_back(RotationDistance(camera.T_cam.rotation(), T.rotation()) * 180.0 /
                                           M_PI / camera.sigma->rotation_deg);
                }
              } catch (const std::exception& e) {
                c.failures.push_back(cell + " seed " + std::to_string(options.seed) + ": " +
                                     e.what());
              }
              std::fprintf(stderr, "\r%s, robot %s, noise %s: seed %d/%d   ", cell.c_str(),
                           r.c_str(), n.c_str(), i + 1, seeds);
            }
          }
          for (const auto& failure : c.failures) std::fprintf(stderr, "%s\n", failure.c_str());
          scenes += c.scenes;
          const int cameras = c.cameras, within_t = c.position_within_2sigma,
                    within_r = c.rotation_within_2sigma;
          std::vector<double> ratio;
          for (size_t i = 0; i < c.position_error_mm.size(); ++i)
            ratio.push_back(c.position_error_mm[i] / c.position_sigma_mm[i]);
          auto beyond_3sigma = [](const std::vector<double>& r) {
            return static_cast<int>(std::count_if(r.begin(), r.end(), [](double x) { return x > 3.0; }));
          };
          auto largest = [](const std::vector<double>& r) {
            return r.empty() ? std::string("-") : Format("%.2f", *std::max_element(r.begin(), r.end()));
          };
          const std::vector<double>& sigma_mm = c.position_sigma_mm;
          const std::vector<double>& error_mm = c.position_error_mm;
          all_cameras += cameras;
          all_t += within_t;
          all_r += within_r;
          table.Add({cell, r, n, off, std::to_string(cameras),
                     most_views ? Format("%d–%d", fewest_views, most_views) : std::string("-"),
                     Format("%.0f %%", 100.0 * within_t / std::max(1, cameras)),
                     Format("%.0f %%", 100.0 * within_r / std::max(1, cameras)),
                     Format("%d, %s", beyond_3sigma(ratio),
                            rotation_ratio.empty() ? "-" : std::to_string(beyond_3sigma(rotation_ratio)).c_str()),
                     Format("%.2f", Median(ratio)), largest(ratio), largest(rotation_ratio), Format("%.3f", Mean(sigma_mm)),
                     Format("%.3f", Mean(error_mm)),
                     Format("%.2f/%.3f", Median(c.robot_sigma_mm), Median(c.robot_sigma_deg))});
        }
  table.Add({"all", "", "", "", std::to_string(all_cameras), "",
             Format("%.1f %%", 100.0 * all_t / std::max(1, all_cameras)),
             Format("%.1f %%", 100.0 * all_r / std::max(1, all_cameras)), "", "", "", "", "", "", ""});
  std::printf("%s", table.Markdown().c_str());
  std::printf("\nmodelled robot σ: median over the scenes, mm/deg per axis (0: the solve did not model it).\n");
  std::printf("\n%d scenes; honest: 85–98 %% of the cameras within 2σ (σ = sqrt of the trace of the 3×3 covariance).\n",
              scenes);
  return 0;
}
