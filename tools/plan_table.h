// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// What `handeye plan` and `handeye advise` share: the plan table and the candidate options.

#include <CLI/CLI.hpp>
#include <cstdint>

#include "handeye/core/plan.h"

namespace handeye::tools {

/// One line per planned pose: its id, the cameras that see the target and
/// every camera's predicted position σ (mm) once it is recorded.
void PrintPlanTable(const PlanCell& cell, const CapturePlan& plan);

/// Adds `--seed`, `--candidates` (the candidate poses drawn in the region)
/// and `--threads` (those they are weighed on).
void AddCandidateOptions(CLI::App* cmd, std::uint64_t* seed, int* candidates, int* threads);

}  // namespace handeye::tools
