// SPDX-License-Identifier: GPL-2.0-or-later
// Is the σ in the result honest? Over simulated cells, detection noise and
// robot pose error, the fraction of cameras whose true position (rotation)
// error lies within 2σ of the estimate. Honest: 85–98 %; lower is
// overconfident, higher uselessly wide. Projected observations (no images).
//
//   bench_uncertainty --cells small,medium,large --robot 0/0,0.1/0.01,0.3/0.03 \
//       --noise 0.1,0.3 --seeds 6 --poses 20
#include <CLI/CLI.hpp>
#include <cstdio>

#include "handeye/core/calibration.h"
#include "handeye/core/transform.h"
#include "handeye/sim/synthetic.h"
#include "support/bench_support.h"

using namespace handeye;
using namespace handeye::bench;

int main(int argc, char** argv) {
  CLI::App app{"handeye: coverage of the result's 1σ against the truth"};
  std::string cells = "small,medium,large", robot = "0/0,0.1/0.01,0.3/0.03", noise = "0.1,0.3";
  int seeds = 6, poses = 20;
  app.add_option("--cells", cells, "cells");
  app.add_option("--robot", robot, "robot pose error σ, MM/DEG per axis, comma-separated");
  app.add_option("--noise", noise, "detection noise σ per image axis (px), comma-separated");
  app.add_option("--seeds", seeds, "scenes per combination");
  app.add_option("--poses", poses, "robot poses per scene");
  CLI11_PARSE(app, argc, argv);

  Table table({"cell", "robot σ", "noise px", "cameras", "e_t ≤ 2σ", "e_θ ≤ 2σ", "median e_t/σ", "mean σ mm",
               "mean e_t mm"});
  int all_cameras = 0, all_t = 0, all_r = 0, scenes = 0;
  for (const std::string& cell : SplitList(cells))
    for (const std::string& r : SplitList(robot))
      for (const std::string& n : SplitList(noise)) {
        const auto slash = r.find('/');
        const double robot_mm = std::stod(r.substr(0, slash)), robot_deg = std::stod(r.substr(slash + 1));
        const double noise_px = std::stod(n);
        SceneOptions options;
        options.cell = cell;
        options.num_cameras = 4;
        options.num_poses = poses;
        options.pose_noise_mm = robot_mm;
        options.pose_noise_deg = robot_deg;
        const SigmaCoverage c = MeasureSigmaCoverage(options, noise_px, seeds, 1001);
        for (const auto& failure : c.failures) std::fprintf(stderr, "%s\n", failure.c_str());
        scenes += c.scenes;
        const int cameras = c.cameras, within_t = c.position_within_2sigma, within_r = c.rotation_within_2sigma;
        std::vector<double> ratio;
        for (size_t i = 0; i < c.position_error_mm.size(); ++i)
          ratio.push_back(c.position_error_mm[i] / c.position_sigma_mm[i]);
        const std::vector<double>& sigma_mm = c.position_sigma_mm;
        const std::vector<double>& error_mm = c.position_error_mm;
        all_cameras += cameras;
        all_t += within_t;
        all_r += within_r;
        table.Add({cell, r, n, std::to_string(cameras), Format("%.0f %%", 100.0 * within_t / std::max(1, cameras)),
                   Format("%.0f %%", 100.0 * within_r / std::max(1, cameras)), Format("%.2f", Median(ratio)),
                   Format("%.3f", Mean(sigma_mm)), Format("%.3f", Mean(error_mm))});
      }
  table.Add({"all", "", "", std::to_string(all_cameras), Format("%.1f %%", 100.0 * all_t / std::max(1, all_cameras)),
             Format("%.1f %%", 100.0 * all_r / std::max(1, all_cameras)), "", "", ""});
  std::printf("%s", table.Markdown().c_str());
  std::printf("\n%d scenes; honest: 85–98 %% of the cameras within 2σ (σ = sqrt of the trace of the 3×3 covariance).\n",
              scenes);
  return 0;
}
