// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye plan CELL -o PLAN.json [--csv PLAN.csv] [--poses N] [--goal-mm S]
// [--seed K] [--intrinsics-sigma S] [--no-cross-terms]`: which robot poses to record (core/plan.h),
// before the robot moves. Exit 3 when a camera can see the target from nowhere in the region, or
// the goal is out of reach (the best σ reachable is named).
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli_numbers.h"
#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/io/plan_json.h"
#include "output_paths.h"
#include "plan_table.h"

namespace handeye::tools {
namespace {

/// With --goal-mm and no --poses, the most poses a plan may take.
constexpr int kMostPosesForGoal = 60;

struct PlanArgs {
  std::string cell;
  std::string output;
  std::string csv;
  int poses = 12;
  bool poses_given = false;
  double goal_mm = 0;
  std::uint64_t seed = 1;
  int candidates = 8000;
  int threads = 0;
  std::string intrinsics_sigma;  // --intrinsics-sigma: the cell's, or the solve's default
  bool no_cross_terms = false;   // the σ of `calibrate --no-cross-terms`
};

void RunPlan(const PlanArgs& args) {
  const std::string csv = !args.csv.empty() ? args.csv
                                            : std::filesystem::path(args.output).replace_extension(".csv").string();
  CheckFileOutputs({{"CELL", args.cell}}, {{"-o", args.output}, {"--csv", csv}});
  PlanCell cell = LoadPlanCell(args.cell);
  if (!args.intrinsics_sigma.empty()) {
    std::string why;
    const auto sigma = ParseIntrinsicsSigma(args.intrinsics_sigma, &why, cell.intrinsics_sigma);
    if (!sigma) throw InputError("", "", "--intrinsics-sigma: " + why);
    cell.intrinsics_sigma = *sigma;
  }
  cell.cross_terms = !args.no_cross_terms;
  PlanOptions options;
  options.poses = args.goal_mm > 0 && !args.poses_given ? kMostPosesForGoal : args.poses;
  options.goal_mm = args.goal_mm;
  options.seed = args.seed;
  options.candidates = args.candidates;
  options.threads = args.threads;
  std::string why;
  if (!options.Check(&why)) throw InputError("", "--poses/--goal-mm", "expected " + why);
  const CapturePlan plan = PlanCapture(cell, options);
  if (!plan.poses.empty()) {
    SavePlan(plan, cell, options, args.output, csv);
    PrintPlanTable(cell, plan);
    std::printf("%zu poses from %d candidates the cameras can see; worst camera %s at %.3f mm -> %s, %s\n",
                plan.poses.size(), plan.candidates, plan.worst_camera.c_str(), plan.worst_position_mm,
                args.output.c_str(), csv.c_str());
  }
  if (!plan.failure.empty()) throw SolveError(plan.failure);
}

}  // namespace

void RegisterPlan(CLI::App& app) {
  auto args = std::make_shared<PlanArgs>();
  CLI::App* cmd = app.add_subcommand("plan", "choose the robot poses to record before a capture (handeye-plan/1)");
  cmd->add_option("CELL", args->cell, "what is known about the cell (handeye-cell/1, docs/formats.md)")->required();
  cmd->add_option("-o,--output", args->output, "plan to write (handeye-plan/1)")->required();
  cmd->add_option("--csv", args->csv, "the poses as id,x,y,z,qx,qy,qz,qw in metres (default: PLAN with .csv)");
  cmd->add_option("--poses", args->poses, "how many poses (with --goal-mm: the most; default 12, 60 with a goal)")
      ->check(IntegerIn(1, 1000, "between 1 and 1000 poses"))
      ->each([args](const std::string&) { args->poses_given = true; });
  cmd->add_option("--goal-mm", args->goal_mm, "stop at the fewest poses whose worst camera sigma is within this (mm)")
      ->check(PositiveNumber("a positive goal in mm"));
  cmd->add_option("--intrinsics-sigma", args->intrinsics_sigma,
                  "how far off the given intrinsics may be, as calibrate takes it (focal=P%,principal_point=Npx "
                  "or 0); default the cell's noise.intrinsics_sigma, else focal=1%,principal_point=3px");
  cmd->add_flag("--no-cross-terms", args->no_cross_terms,
                "predict the sigma of calibrate --no-cross-terms (the same poses are chosen)");
  AddCandidateOptions(cmd, &args->seed, &args->candidates, &args->threads);
  cmd->callback([args]() { RunPlan(*args); });
}

HANDEYE_SUBCOMMAND(5, RegisterPlan);

}  // namespace handeye::tools
