// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye report DATASET RESULT -o DIR`: per-view overlays, plots and an
// HTML page for a person to accept or reject a calibration (SPEC §7), drawn
// off-screen.
#include "handeye/report/report.h"

#include <cstdio>
#include <iostream>
#include <memory>

#include "argument_order.h"
#include "cli_numbers.h"
#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/detection.h"
#include "handeye/io/result_json.h"
#include "report_folder.h"

namespace handeye::tools {
namespace {

struct ReportArgs {
  bool quiet = false;  // --quiet: no progress line
  std::string dataset;
  std::string result;
  std::string output;
  std::string observations;
  int threads = 0;
  bool no_closed_form = false;
  bool reorthonormalise = false;
  int next_poses = 4;
  double next_goal_mm = 0;
};

void RunReport(const ReportArgs& args) {
  CheckArgumentOrder("handeye report DATASET RESULT -o DIR",
                     {{"DATASET", args.dataset, {"handeye-dataset/1", "handeye-observations/1"}},
                      {"RESULT", args.result, {"handeye-result/1"}}});
  LoadOptions load;
  load.reorthonormalise = args.reorthonormalise;
  std::vector<Warning> warnings;
  Dataset dataset = LoadDataset(args.dataset, load, &warnings);
  PrintWarnings(warnings);
  const CalibrationResult result = LoadResult(args.result);
  std::vector<NamedPath> inputs = ImageInputs(dataset);
  inputs.insert(
      inputs.end(),
      {{"DATASET", args.dataset}, {"RESULT", args.result}, {"--observations", args.observations}});
  CheckReportFolder(inputs, {}, {"-o", args.output});

  // Where the detected points come from: an observations file given beside
  // the dataset (its images are still drawn on), the dataset's own, or a
  // detection run now.
  std::string points_file = args.dataset;
  if (!args.observations.empty()) {
    Dataset observed = LoadDataset(args.observations, load);
    dataset.observations = std::move(observed.observations);
    points_file = args.observations;
  } else if (dataset.observations.empty()) {
    bool has_images = false;
    for (const auto& pose : dataset.poses) has_images = has_images || !pose.images.empty();
    if (!has_images)
      throw InputError(args.dataset, "/observations",
                       "observations, or poses with images to detect in");
    DetectOptions detect;
    detect.threads = args.threads;
    detect.progress = ProgressLine("detecting", args.quiet);
    DetectAll(&dataset, detect);
  }

  ReportOptions options;
  options.threads = args.threads;
  options.compare_closed_form = !args.no_closed_form;
  options.next_poses = args.next_poses;
  options.next_goal_mm = args.next_goal_mm;
  options.dataset_label =
      args.dataset + (args.observations.empty() ? "" : " + " + args.observations);
  options.result_label = args.result;
  options.progress = ProgressLine("drawing overlays", args.quiet);
  ReportSummary summary;
  try {
    summary = WriteReportFolder(dataset, result, args.output, options);
  } catch (const InputError& e) {
    if (!e.file().empty()) throw;
    // The model names the JSON path; observations come from the points file,
    // everything else (setup, cameras) is the result disagreeing with the dataset.
    throw e.WithFile(e.json_path().rfind("/observations", 0) == 0 ? points_file : args.result);
  }
  PrintWarnings(summary.warnings);
  std::fprintf(stderr, "wrote %s (%d overlays, %zu warnings) in %.2f s\n",
               summary.index_html.c_str(), summary.overlays, summary.warnings.size(),
               summary.seconds);
}

}  // namespace

void RegisterReport(CLI::App& app) {
  auto args = std::make_shared<ReportArgs>();
  CLI::App* cmd =
      app.add_subcommand("report", "overlay PNGs and an HTML report of a calibration, off-screen");
  cmd->add_option("DATASET", args->dataset,
                  "handeye-dataset/1 (images; detects when it has no observations) or "
                  "handeye-observations/1")
      ->required();
  cmd->add_option("RESULT", args->result, "handeye-result/1 computed from that dataset")
      ->required();
  cmd->add_option("-o,--output", args->output,
                  "report folder to write (index.html with the plots, overlays/, thumbs/)")
      ->required();
  cmd->add_option(
      "--observations", args->observations,
      "handeye-observations/1 with the detected points (instead of detecting in DATASET's images)");
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(ThreadCount());
  cmd->add_flag("--no-closed-form", args->no_closed_form,
                "leave out the result's comparison with a per-camera closed-form solution (its table column)");
  cmd->add_option("--next-poses", args->next_poses,
                  "robot poses proposed in the report's \"what to capture next\" section, as `handeye "
                  "advise` proposes them (default 4; 0 leaves the section out)")
      ->check(IntegerIn(0, 20, "between 0 and 20 poses"));
  cmd->add_option("--next-goal-mm", args->next_goal_mm,
                  "name the cameras predicted above this position sigma (mm) in that section, and "
                  "stop proposing once all are within it (default: no goal)")
      ->check(NonNegativeNumber("a number of millimetres, 0 or more"));
  cmd->add_flag("--reorthonormalise", args->reorthonormalise,
                "replace slightly non-orthonormal robot rotations by the nearest rotation");
  AddQuietFlag(cmd, &args->quiet);
  cmd->callback([args]() { RunReport(*args); });
}

HANDEYE_SUBCOMMAND(30, RegisterReport);

}  // namespace handeye::tools
