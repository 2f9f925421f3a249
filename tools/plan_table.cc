// SPDX-License-Identifier: GPL-2.0-or-later
#include "plan_table.h"

#include <cstdio>
#include <string>

#include "cli_numbers.h"

namespace handeye::tools {

void PrintPlanTable(const PlanCell& cell, const CapturePlan& plan) {
  std::printf("%-6s %-28s", "pose", "seen by");
  for (const PlanCamera& camera : cell.cameras) std::printf(" %9s", camera.camera.name.c_str());
  std::printf("   (predicted position sigma, mm)\n");
  for (const PlannedPose& pose : plan.poses) {
    std::string seen;
    for (const std::string& name : pose.cameras) seen += (seen.empty() ? "" : ",") + name;
    std::printf("%-6s %-28s", pose.id.c_str(), seen.c_str());
    for (const PlanCamera& camera : cell.cameras) std::printf(" %9.3f", pose.sigma_after.at(camera.camera.name).position_mm);
    std::printf("\n");
  }
}

void AddCandidateOptions(CLI::App* cmd, std::uint64_t* seed, int* candidates, int* threads) {
  cmd->add_option("--seed", *seed, "seed of the candidate poses drawn in the region")
      ->check(UnsignedInteger("a whole number from 0 to 2^64 - 1"));
  cmd->add_option("--candidates", *candidates, "candidate poses drawn in the region's box (default 8000)")
      ->check(IntegerIn(1, 1000000, "between 1 and 1000000 candidates"));
  cmd->add_option("--threads", *threads, "threads the candidates are weighed on (0 = all cores)")
      ->check(IntegerIn(0, 1024, "0 (all cores) to 1024 threads"));
}

}  // namespace handeye::tools
