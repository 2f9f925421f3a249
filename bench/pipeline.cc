// SPDX-License-Identifier: GPL-2.0-or-later
// Speed, memory and accuracy of the whole pipeline on one rendered dataset
// (default: METRIC's synthetic medium cell, 4 cameras × 251 poses at
// 1920×1080): detect, solve and report separately at 1 and 2 threads, the
// detection time per image with and without the target, then the full
// `handeye calibrate` from images as a separate process.
//
//   bench_pipeline --handeye build/tools/handeye --workdir /tmp/handeye-bench
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "handeye/core/calibration.h"
#include "handeye/core/evaluation.h"
#include "handeye/core/uncertainty.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/detection.h"
#include "handeye/io/image.h"
#include "handeye/report/report.h"
#include "handeye/sim/simulation.h"
#include "support/bench_support.h"

extern char** environ;

using namespace handeye;
using namespace handeye::bench;

namespace {

struct ProcessRun {
  int exit_code = -1;
  double seconds = 0;
  double peak_rss_mib = 0;
};

/// Runs a program, waits, and reads its peak RSS from the kernel (wait4).
ProcessRun RunProcess(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  ProcessRun run;
  const Stopwatch watch;
  pid_t pid = 0;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  if (posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ) != 0) return run;
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  run.seconds = watch.Seconds();
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.peak_rss_mib = usage.ru_maxrss / 1024.0;
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  // The same allocator policy as the handeye program, so the stages run here
  // measure what the program does.
  handeye::ReuseFreedImageMemory();
  CLI::App app{"handeye pipeline benchmark: detect, solve, report and full calibrate"};
  std::string handeye = "build/tools/handeye", workdir = "/tmp/handeye-bench", preset = "metric-medium",
              threads_list = "1,2", json_path;
  int poses = 251;
  bool reuse = false;
  app.add_option("--handeye", handeye, "the handeye program, for the full run");
  app.add_option("--workdir", workdir, "where the rendered dataset and outputs go");
  app.add_option("--preset", preset, "simulate --preset/--cell value");
  app.add_option("--poses", poses, "robot poses");
  app.add_option("--threads", threads_list, "comma-separated thread counts");
  app.add_flag("--reuse", reuse, "reuse a dataset already rendered in --workdir");
  app.add_option("--json", json_path, "also write the numbers to this JSON file");
  CLI11_PARSE(app, argc, argv);
  namespace fs = std::filesystem;
  const std::string data = workdir + "/dataset";

  if (!reuse || !fs::exists(data + "/dataset.json")) {
    fs::remove_all(data);
    std::vector<std::string> sim = {handeye, "simulate", data, "--poses", std::to_string(poses), "--seed", "1"};
    if (preset == "metric-medium") {
      sim.insert(sim.end(), {"--preset", "metric-medium"});
    } else {
      sim.insert(sim.end(), {"--cell", preset});
    }
    const ProcessRun run = RunProcess(sim);
    if (run.exit_code != 0) {
      std::fprintf(stderr, "simulate failed (exit %d)\n", run.exit_code);
      return 1;
    }
    std::fprintf(stderr, "rendered %s in %.1f s\n", data.c_str(), run.seconds);
  }
  const GroundTruth truth = LoadGroundTruth(data + "/ground_truth.json");
  size_t images = 0;
  {
    const Dataset d = LoadDataset(data + "/dataset.json");
    for (const auto& p : d.poses) images += p.images.size();
  }

  Table table({"stage", "threads", "wall s", "peak RSS MiB", "notes"});
  nlohmann::ordered_json json;
  CalibrationResult last_result;
  Dataset last_dataset;
  for (const std::string& t : SplitList(threads_list)) {
    const int threads = std::stoi(t);
    ResetPeakRss();
    Stopwatch watch;
    Dataset dataset = LoadDataset(data + "/dataset.json");
    DetectOptions detect;
    detect.threads = threads;
    DetectAll(&dataset, detect);
    const double detect_s = watch.Seconds();
    table.Add({"detect", t, Format("%.2f", detect_s), Format("%.0f", PeakRssMiB()),
               Format("%zu images, %zu views found, %.1f ms/image", images, dataset.observations.size(),
                      1000.0 * detect_s * threads / images)});

    ResetPeakRss();
    watch = Stopwatch();
    CalibrationOptions options;
    options.threads = threads;
    const CalibrationResult result = Calibrate(dataset, options);
    const double solve_s = watch.Seconds();
    table.Add({"solve", t, Format("%.3f", solve_s), Format("%.0f", PeakRssMiB()),
               Format("%d iterations", result.solver.iterations)});

    ResetPeakRss();
    watch = Stopwatch();
    ReportOptions report;
    report.threads = threads;
    const ReportSummary summary = WriteReport(dataset, result, workdir + "/report", report);
    const double report_s = watch.Seconds();
    table.Add({"report", t, Format("%.2f", report_s), Format("%.0f", PeakRssMiB()),
               Format("%d overlays", summary.overlays)});
    json["stages"][t] = {{"detect_s", detect_s}, {"solve_s", solve_s}, {"report_s", report_s}};
    last_result = result;
    last_dataset = std::move(dataset);
  }

  // Images with and without the target apart: on a camera network most
  // images show no target, and they cost differently. One thread, each image
  // on the process's CPU clock.
  {
    Dataset timed = LoadDataset(data + "/dataset.json");
    const std::vector<ImageTiming> timings = DetectTimed(&timed);
    for (const bool found : {true, false}) {
      const ClassTiming c = SummariseTimings(timings, found);
      const double per_second = c.mean_ms > 0 ? 1000.0 / c.mean_ms : 0.0;
      table.Add({found ? "detect: images with the target" : "detect: images without it", "1", "", "",
                 Format("%d images, %.1f ms CPU each (median %.1f, max %.1f; decode %.1f), %.0f images/s",
                        c.images, c.mean_ms, c.median_ms, c.max_ms, c.mean_load_ms, per_second)});
      json["per_image"][found ? "with_target" : "without_target"] = {
          {"images", c.images},       {"mean_cpu_ms", c.mean_ms}, {"median_cpu_ms", c.median_ms},
          {"max_cpu_ms", c.max_ms},   {"decode_cpu_ms", c.mean_load_ms},
          {"images_per_s", per_second}};
    }
  }

  const ProcessRun full = RunProcess({handeye, "calibrate", data + "/dataset.json", "-o", workdir + "/result.json"});
  table.Add({"handeye calibrate (images → result)", "all", Format("%.2f", full.seconds),
             Format("%.0f", full.peak_rss_mib), Format("exit %d", full.exit_code)});
  json["full"] = {{"seconds", full.seconds}, {"peak_rss_mib", full.peak_rss_mib}, {"exit", full.exit_code}};

  const Evaluation eval = EvaluateAgainstTruth(last_result, truth);
  // The bound at the truth for the noise the detector showed: the RMS of the
  // final residuals per coordinate.
  const double sigma = last_result.metrics.rms_px / std::sqrt(2.0);
  CalibrationResult at = last_result;
  for (auto& cam : at.cameras)
    if (truth.T_cam.count(cam.name)) cam.T_cam = truth.T_cam.at(cam.name);
  at.T_target = truth.T_target;
  const PositionCovariance bound = ComputePositionCovariance(last_dataset, at, sigma);
  std::vector<double> traces, errors;
  for (const auto& c : eval.cameras) {
    traces.push_back(bound.camera_position.at(c.name).trace());
    errors.push_back(c.translation_mm / 1000.0);
  }
  const double bound_mm = 1000.0 * std::sqrt(Mean(traces));
  const double error_mm = 1000.0 * Rms(errors);
  std::printf("### Pipeline on %s, %d poses, %zu images (machine: %u cores)\n\n%s\n", preset.c_str(), poses, images,
              std::thread::hardware_concurrency(), table.Markdown().c_str());
  std::printf("accuracy: mean e_t^GT %.3f mm, mean e_θ^GT %.4f deg; residual σ %.3f px per coordinate; "
              "RMS position error %.3f mm vs Cramér–Rao bound %.3f mm (ratio %.2f)\n",
              eval.mean_translation_mm, eval.mean_rotation_deg, sigma, error_mm, bound_mm, error_mm / bound_mm);
  json["accuracy"] = {{"e_t_gt_mm", eval.mean_translation_mm}, {"e_theta_gt_deg", eval.mean_rotation_deg},
                      {"sigma_px", sigma}, {"rms_position_error_mm", error_mm}, {"bound_mm", bound_mm}};
  if (!json_path.empty()) std::ofstream(json_path) << json.dump(2) << "\n";
  return 0;
}
