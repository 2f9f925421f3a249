// SPDX-License-Identifier: GPL-2.0-or-later
#include "plan_table.h"

#include <cstdio>
#include <string>

#include "cli_numbers.h"

namespace handeye::tools {

namespace {

/// Where a camera's σ after the plan would be under 80 % of itself were
/// its intrinsics, or the robot, exact: what it would be, and what to do.
void PrintSigmaLimits(const PlanCell& cell, const CapturePlan& plan) {
  if (plan.poses.empty()) return;
  constexpr double kNotable = 0.8;
  bool header = false, intrinsics = false, robot = false;
  for (const PlanCamera& camera : cell.cameras) {
    const std::string& name = camera.camera.name;
    const double sigma = plan.poses.back().sigma_after.at(name).position_mm;
    const auto known = plan.intrinsics_exact_mm.find(name);
    const auto exact = plan.robot_exact_mm.find(name);
    if (known == plan.intrinsics_exact_mm.end() || exact == plan.robot_exact_mm.end()) continue;
    const bool by_intrinsics = known->second < kNotable * sigma,
               by_robot = exact->second < kNotable * sigma;
    if (!by_intrinsics && !by_robot) continue;
    if (!header)
      std::printf(
          "what holds the sigma back (position sigma, mm, of the same poses):\n  %-12s %9s %17s "
          "%12s\n",
          "camera", "planned", "intrinsics exact", "robot exact");
    header = true;
    intrinsics = intrinsics || by_intrinsics;
    robot = robot || by_robot;
    std::printf("  %-12s %9.3f %17.3f %12.3f\n", name.c_str(), sigma, known->second, exact->second);
  }
  if (intrinsics)
    std::printf(
        "  intrinsics: the focal length trades against the distance along the camera's axis; views "
        "at\n"
        "  more varied depths, or nearer the camera, pin it, and so do intrinsics from a dedicated "
        "calibration\n");
  if (robot) std::printf("  robot: its pose error, which more poses average\n");
  if (intrinsics && robot)
    std::printf(
        "  both at once: the robot's moves along the axis are what pin the focal length, and its "
        "error blurs them\n");
}

}  // namespace

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
  PrintSigmaLimits(cell, plan);
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
