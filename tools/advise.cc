// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye advise RESULT|DATASET|OBS [--goal-mm S] [--poses K] [--cell CELL]
// [-o NEXT.json]`: after a (partial) capture, which cameras are above the goal
// and which K poses to record next (core/plan_advice.h). A dataset or
// observations file is calibrated first; a result names its input.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli_numbers.h"
#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/core/plan_advice.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/detection.h"
#include "handeye/io/json_util.h"
#include "handeye/io/plan_json.h"
#include "handeye/io/result_json.h"
#include "output_paths.h"
#include "plan_table.h"

namespace handeye::tools {
namespace {

struct AdviseArgs {
  std::string input;
  std::string dataset;  // --dataset: the capture a RESULT was solved from
  std::string cell;
  std::string output;
  int poses = 4;
  double goal_mm = 0;
  std::uint64_t seed = 1;
  int candidates = 8000;
  int threads = 0;
  bool quiet = false;
};

bool IsResult(const std::string& path) {
  const nlohmann::json json = ReadJsonFile(path);
  return json.is_object() && json.contains("format") && json["format"] == "handeye-result/1";
}

Dataset LoadCapture(const std::string& path, bool quiet) {
  std::vector<Warning> warnings;
  Dataset dataset = LoadDataset(path, {}, &warnings);
  PrintWarnings(warnings);
  if (dataset.observations.empty()) {
    DetectOptions detect;
    detect.progress = ProgressLine("detecting", quiet);
    PrintWarnings(DetectAll(&dataset, detect));
  }
  return dataset;
}

void PrintAdvice(const PlanCell& cell, const Advice& advice, const AdviseArgs& args) {
  std::printf("%-12s %12s %12s\n", "camera", "sigma mm", "sigma deg");
  for (const auto& [name, sigma] : advice.now)
    std::printf("%-12s %12.3f %12.4f\n", name.c_str(), sigma.position_mm, sigma.rotation_deg);
  if (args.goal_mm > 0) {
    std::string above;
    for (const std::string& name : advice.above_goal) above += " " + name;
    if (above.empty())
      std::printf("every camera is within the goal of %.3f mm\n", args.goal_mm);
    else
      std::printf("above the goal of %.3f mm:%s\n", args.goal_mm, above.c_str());
  }
  if (advice.next.poses.empty()) return;
  std::printf("what to capture next:\n");
  PrintPlanTable(cell, advice.next);
}

void RunAdvise(const AdviseArgs& args) {
  const bool from_result = IsResult(args.input);
  std::string capture = args.dataset;
  CalibrationResult result;
  if (from_result) {
    result = LoadResult(args.input);
    if (capture.empty()) capture = result.input;
    if (capture.empty())
      throw InputError(args.input, "/provenance/input", "the capture it was solved from; give it with --dataset");
  } else {
    capture = args.input;
  }
  CheckFileOutputs({{"INPUT", args.input}, {"--dataset", capture}, {"--cell", args.cell}}, {{"-o", args.output}});
  const Dataset dataset = LoadCapture(capture, args.quiet);
  if (!from_result) result = Calibrate(dataset, CalibrationOptions{});
  std::optional<PlanCell> given;
  if (!args.cell.empty()) given = LoadPlanCell(args.cell);
  const PlanCell cell = PlanCellOfResult(dataset, result, given);
  std::string why;
  if (!cell.Check(&why)) throw InputError(capture, "", "a capture to advise on: expected " + why);
  PlanOptions options;
  options.poses = args.poses;
  options.goal_mm = args.goal_mm;
  options.seed = args.seed;
  options.candidates = args.candidates;
  options.threads = args.threads;
  const Advice advice = Advise(cell, RecordedPoses(dataset, result), options);
  PrintAdvice(cell, advice, args);
  if (!args.output.empty() && !advice.next.poses.empty())
    SavePlan(advice.next, cell, options, args.output,
             std::filesystem::path(args.output).replace_extension(".csv").string());
  // A goal the proposals do not reach is advice too, not a failure of the
  // command; a camera no candidate lets see the target is one.
  if (!advice.next.failure.empty() && advice.next.failure.rfind("the goal", 0) != 0)
    throw SolveError(advice.next.failure);
  if (!advice.next.failure.empty()) std::printf("%s\n", advice.next.failure.c_str());
}

}  // namespace

void RegisterAdvise(CLI::App& app) {
  auto args = std::make_shared<AdviseArgs>();
  CLI::App* cmd = app.add_subcommand("advise", "after a capture: cameras above the goal and the poses to record next");
  cmd->add_option("INPUT", args->input, "a result (handeye-result/1), or the capture (dataset or observations)")
      ->required();
  cmd->add_option("--dataset", args->dataset, "the capture a RESULT was solved from (default: the one it names)");
  cmd->add_option("--cell", args->cell,
                  "the region and view limits (handeye-cell/1; default: the region the capture's poses span)");
  cmd->add_option("-o,--output", args->output, "write the proposed poses (handeye-plan/1, and a .csv beside it)");
  cmd->add_option("--poses", args->poses, "how many poses to propose (default 4)")
      ->check(IntegerIn(1, 1000, "between 1 and 1000 poses"));
  cmd->add_option("--goal-mm", args->goal_mm, "the position sigma each camera should reach (mm)")
      ->check(PositiveNumber("a positive goal in mm"));
  AddCandidateOptions(cmd, &args->seed, &args->candidates, &args->threads);
  AddQuietFlag(cmd, &args->quiet);
  cmd->callback([args]() { RunAdvise(*args); });
}

HANDEYE_SUBCOMMAND(27, RegisterAdvise);

}  // namespace handeye::tools
