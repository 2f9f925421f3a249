// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The capture planner's files (docs/formats.md): `handeye-cell/1`, what is
/// known about a cell before a capture (core/plan.h PlanCell), and
/// `handeye-plan/1`, the poses `handeye plan` chose, with a CSV a robot
/// program can step through. Loaders throw InputError naming the file, the
/// JSON path and what was expected.

#include <string>
#include <vector>

#include "handeye/core/plan.h"
#include "handeye/io/pose_formats.h"

namespace handeye {

/// Reads a `handeye-cell/1` file.
PlanCell LoadPlanCell(const std::string& path);
/// Writes `handeye-cell/1` (atomically).
void SavePlanCell(const PlanCell& cell, const std::string& path);

/// Writes `handeye-plan/1` (the poses as 4×4 `T_base_ee`, the cameras that
/// see the target at each and the σ predicted after each) to `json_path`, and
/// when `csv_path` is not empty the poses as `id,x,y,z,qx,qy,qz,qw` (metres;
/// what `handeye import-poses` reads). `options` and `cell` are recorded.
void SavePlan(const CapturePlan& plan, const PlanCell& cell, const PlanOptions& options, const std::string& json_path,
              const std::string& csv_path);

/// The robot poses of a pose file: a JSON file with `poses` [{id, T_base_ee}]
/// (a plan, a dataset or an observations file; T_base_ee in any form of SPEC
/// §4), or a CSV / YAML pose list as `handeye import-poses` reads it (metres).
std::vector<PoseRow> ReadPoseFile(const std::string& path);

}  // namespace handeye
