// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye check RESULT DATASET|OBS [-o CHECK.json] [--tolerance-mm 1]
// [--tolerance-deg 0.1]`: has a camera moved since calibration? Exit 0 when
// none did, 4 when some did, 3 when none did but some could not be assessed
// (SPEC §7).
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "argument_order.h"
#include "cli_numbers.h"
#include "commands.h"
#include "handeye/core/drift.h"
#include "handeye/core/error.h"
#include "handeye/io/atomic_file.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/detection.h"
#include "handeye/io/json_util.h"
#include "handeye/io/result_json.h"
#include "handeye/io/warning_json.h"
#include "output_paths.h"

namespace handeye::tools {
namespace {

struct CheckArgs {
  std::string result;
  std::string input;
  std::string output;
  double tolerance_mm = 1.0;
  double tolerance_deg = 0.1;
  int threads = 0;
  bool quiet = false;
};

void WriteCheck(const DriftResult& drift, const DriftOptions& options, const std::string& path) {
  nlohmann::ordered_json cameras = nlohmann::ordered_json::object();
  for (const CameraDrift& c : drift.cameras) {
    nlohmann::ordered_json entry;
    entry["verdict"] = c.verdict;
    if (!c.reason.empty()) entry["reason"] = c.reason;
    entry["views"] = c.views;
    if (c.estimated) {
      entry["moved_mm"] = c.moved_mm;
      entry["moved_deg"] = c.moved_deg;
      entry["sigma_mm"] = c.sigma_mm;
      entry["sigma_deg"] = c.sigma_deg;
    }
    cameras[c.name] = entry;
  }
  nlohmann::ordered_json root;
  root["format"] = "handeye-check/1";
  root["tolerance_mm"] = options.tolerance_mm;
  root["tolerance_deg"] = options.tolerance_deg;
  root["cameras"] = cameras;
  AddWarningsJson(drift.warnings, &root);
  WriteFileAtomically(path, DumpJson(root));
}

void PrintTable(const DriftResult& drift) {
  std::printf("%-12s %9s %9s %9s %9s %6s  %s\n", "camera", "moved mm", "± mm", "moved °", "± °",
              "views", "verdict");
  for (const CameraDrift& c : drift.cameras) {
    const std::string verdict = c.verdict + (c.reason.empty() ? "" : " (" + c.reason + ")");
    if (!c.estimated)
      std::printf("%-12s %9s %9s %9s %9s %6d  %s\n", c.name.c_str(), "-", "-", "-", "-", c.views,
                  verdict.c_str());
    else
      std::printf("%-12s %9.2f %9.2f %9.3f %9.3f %6d  %s\n", c.name.c_str(), c.moved_mm, c.sigma_mm,
                  c.moved_deg, c.sigma_deg, c.views, verdict.c_str());
  }
}

// The command that recalibrates the moved cameras, the ones found in place
// held (none held: a plain calibration).
std::string RecalibrateCommand(const DriftResult& drift, const CheckArgs& args) {
  std::string kept;
  for (const CameraDrift& c : drift.cameras)
    if (c.verdict == "ok") kept += (kept.empty() ? "" : ",") + c.name;
  std::string command = "handeye calibrate " + args.input + " -o NEW.json";
  if (!kept.empty()) command += " --from " + args.result + " --keep-cameras " + kept;
  return command;
}

// Exit 4 when a camera moved; else 3 when one could not be assessed (a script
// must not read "cannot tell" as "nothing moved"); else 0.
void ReportOutcome(const DriftResult& drift, const DriftOptions& options, const CheckArgs& args) {
  std::string moved, unknown;
  for (const CameraDrift& c : drift.cameras) {
    if (c.verdict == "moved") moved += (moved.empty() ? "" : ", ") + c.name;
    if (c.verdict == "not_assessed") unknown += (unknown.empty() ? "" : ", ") + c.name;
  }
  if (!unknown.empty())
    std::fprintf(stderr, "not assessed (the new data cannot tell whether they moved): %s\n",
                 unknown.c_str());
  if (!moved.empty()) {
    std::fprintf(stderr, "moved beyond %.3g mm / %.3g deg: %s; recalibrate %s with `%s`\n",
                 options.tolerance_mm, options.tolerance_deg, moved.c_str(),
                 moved.find(',') == std::string::npos ? "it" : "them",
                 RecalibrateCommand(drift, args).c_str());
    throw ExitStatus{4};
  }
  if (!unknown.empty()) throw ExitStatus{3};
}

void RunCheck(const CheckArgs& args) {
  DriftOptions options;
  options.tolerance_mm = args.tolerance_mm;
  options.tolerance_deg = args.tolerance_deg;
  options.threads = args.threads > 0 ? args.threads : 1;
  CheckArgumentOrder(
      "handeye check RESULT DATASET|OBS",
      {{"RESULT", args.result, {"handeye-result/1"}},
       {"DATASET|OBS", args.input, {"handeye-dataset/1", "handeye-observations/1"}}});
  const CalibrationResult calibration = LoadResult(args.result);
  std::vector<Warning> warnings;
  Dataset dataset = LoadDataset(args.input, {}, &warnings);
  PrintWarnings(warnings);
  std::vector<NamedPath> inputs = ImageInputs(dataset);
  inputs.insert(inputs.end(), {{"RESULT", args.result}, {"INPUT", args.input}});
  CheckFileOutputs(inputs, {{"-o", args.output}});
  if (dataset.observations.empty()) {
    DetectOptions detect;
    detect.threads = args.threads;
    detect.progress = ProgressLine("detecting", args.quiet);
    DetectAll(&dataset, detect);
  }
  DriftResult drift;
  try {
    drift = CheckDrift(dataset, calibration, options);
  } catch (const InputError& e) {
    throw e.file().empty() ? e.WithFile(args.input) : e;
  }
  PrintWarnings(drift.warnings);
  PrintTable(drift);
  if (!args.output.empty()) {
    WriteCheck(drift, options, args.output);
    std::fprintf(stderr, "wrote %s\n", args.output.c_str());
  }
  ReportOutcome(drift, options, args);
}

void RegisterCheck(CLI::App& app) {
  auto args = std::make_shared<CheckArgs>();
  CLI::App* cmd = app.add_subcommand("check",
                                     "has a camera moved since calibration? (exit 4 when one did, "
                                     "3 when one could not be assessed)");
  cmd->add_option("RESULT", args->result, "the calibration (handeye-result/1)")->required();
  cmd->add_option("INPUT", args->input, "new poses with images (handeye-dataset/1) or observations")->required();
  cmd->add_option("-o,--output", args->output, "write handeye-check/1 here");
  cmd->add_option("--tolerance-mm", args->tolerance_mm, "a camera moved when its centre moved more (default 1)")
      ->check(PositiveNumber("a positive distance in mm"));
  cmd->add_option("--tolerance-deg", args->tolerance_deg, "… or it turned more (default 0.1)")
      ->check(PositiveNumber("a positive angle in degrees"));
  cmd->add_option("--threads", args->threads, "threads for detection (0 = all cores)")->check(ThreadCount());
  AddQuietFlag(cmd, &args->quiet);
  cmd->callback([args]() { RunCheck(*args); });
}

}  // namespace

HANDEYE_SUBCOMMAND(25, RegisterCheck);

}  // namespace handeye::tools
