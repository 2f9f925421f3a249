// SPDX-License-Identifier: GPL-2.0-or-later
// How the joint solve scales: cameras × poses at the observation level
// (projected points + noise), solve time, peak memory and accuracy.
//
//   bench_scale --cameras 2,4,8,16,32 --poses 50,200,1000 --threads 1
#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/evaluation.h"
#include "support/bench_support.h"

using namespace handeye;
using namespace handeye::bench;

namespace {

// User + system time of the whole process, all threads (seconds): on a
// shared machine the wall time says little, the CPU time does.
double ProcessCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"handeye scaling benchmark: joint solve time and memory by cameras × poses"};
  std::string cameras_list = "2,4,8,16,32", poses_list = "50,200,1000", cell = "large", json_path;
  double noise_px = 0.2, robot_mm = 0.0, robot_deg = 0.0;
  int threads = 1;
  std::uint64_t seed = 1;
  app.add_option("--cameras", cameras_list, "comma-separated camera counts");
  app.add_option("--poses", poses_list, "comma-separated pose counts");
  app.add_option("--cell", cell, "small, medium or large (room for many cameras on the ring)");
  app.add_option("--noise-px", noise_px, "pixel noise σ of the projected observations");
  app.add_option("--robot-mm", robot_mm,
                 "robot pose error: translation σ per axis (mm); 0 = exact");
  app.add_option("--robot-deg", robot_deg,
                 "robot pose error: rotation σ (deg, a turn about a random axis)");
  app.add_option("--threads", threads, "Ceres threads");
  app.add_option("--seed", seed, "scene seed");
  app.add_option("--json", json_path, "also write the numbers to this JSON file");
  CLI11_PARSE(app, argc, argv);

  Table table({"cameras", "poses", "views", "residuals (pts)", "scene s", "solve s", "CPU s", "iterations",
               "peak RSS MiB", "e_t^GT mm", "e_θ^GT deg"});
  nlohmann::ordered_json json = nlohmann::ordered_json::array();
  for (const std::string& c : SplitList(cameras_list))
    for (const std::string& p : SplitList(poses_list)) {
      SceneOptions options;
      options.cell = cell;
      options.num_cameras = std::stoi(c);
      options.num_poses = std::stoi(p);
      options.seed = seed;
      options.pose_noise_mm = robot_mm;
      options.pose_noise_deg = robot_deg;
      const Stopwatch scene_watch;
      SyntheticScene scene = MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
      std::mt19937_64 rng(seed);
      AddProjectedObservations(&scene, noise_px, &rng);
      const double scene_s = scene_watch.Seconds();
      size_t points = 0;
      for (const auto& obs : scene.dataset.observations) points += obs.ids.size();
      CalibrationOptions calib;
      calib.threads = threads;
      ResetPeakRss();
      const Stopwatch watch;
      const double cpu_start = ProcessCpuSeconds();
      std::string cells[6];
      try {
        const CalibrationResult result = Calibrate(scene.dataset, calib);
        const double seconds = watch.Seconds();
        const double cpu_seconds = ProcessCpuSeconds() - cpu_start;
        const Evaluation eval = EvaluateAgainstTruth(result, scene.truth);
        table.Add({c, p, Format("%zu", scene.dataset.observations.size()), Format("%zu", points),
                   Format("%.2f", scene_s), Format("%.3f", seconds), Format("%.3f", cpu_seconds),
                   Format("%d", result.solver.iterations),
                   Format("%.0f", PeakRssMiB()), Format("%.3f", eval.mean_translation_mm),
                   Format("%.4f", eval.mean_rotation_deg)});
        json.push_back({{"cameras", std::stoi(c)}, {"poses", std::stoi(p)},
                        {"views", scene.dataset.observations.size()}, {"points", points},
                        {"solve_seconds", seconds}, {"cpu_seconds", cpu_seconds},
                        {"iterations", result.solver.iterations},
                        {"peak_rss_mib", PeakRssMiB()}, {"e_t_gt_mm", eval.mean_translation_mm},
                        {"e_theta_gt_deg", eval.mean_rotation_deg}});
      } catch (const std::exception& e) {
        table.Add({c, p, Format("%zu", scene.dataset.observations.size()), Format("%zu", points),
                   Format("%.2f", scene_s), "failed", "-", "-", "-", "-", e.what()});
      }
      std::fprintf(stderr, "\r%s cameras x %s poses done   ", c.c_str(), p.c_str());
    }
  std::fprintf(stderr, "\n");
  std::printf(
      "### Joint solve scaling (%s cell, projected points, σ %.2f px, robot %.2f mm / %.3f deg, %d "
      "thread(s))\n\n%s",
      cell.c_str(), noise_px, robot_mm, robot_deg, threads, table.Markdown().c_str());
  if (!json_path.empty()) std::ofstream(json_path) << json.dump(2) << "\n";
  return 0;
}
