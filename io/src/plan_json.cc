// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye-plan/1` and its CSV (io/plan_json.h), and pose files for `simulate --poses-file`.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

#include "cell_json_internal.h"
#include "handeye/core/error.h"
#include "handeye/io/atomic_file.h"
#include "handeye/io/json_util.h"
#include "handeye/io/plan_json.h"

namespace handeye {
namespace {

constexpr char kPlanFormat[] = "handeye-plan/1";

nlohmann::ordered_json SigmaJson(const std::map<std::string, PredictedSigma>& sigma) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const auto& [name, s] : sigma)
    out[name] = {{"position_mm", s.position_mm}, {"rotation_deg", s.rotation_deg}, {"own_position_mm", s.own_position_mm}};
  return out;
}

std::string PlanCsv(const CapturePlan& plan) {
  std::ostringstream csv;
  csv.precision(9);
  csv << "id,x,y,z,qx,qy,qz,qw\n";
  for (const PlannedPose& pose : plan.poses) {
    const Eigen::Quaterniond q(pose.T_base_ee.linear());
    const Eigen::Vector3d t = pose.T_base_ee.translation();
    csv << pose.id << "," << t.x() << "," << t.y() << "," << t.z() << "," << q.x() << "," << q.y() << "," << q.z()
        << "," << q.w() << "\n";
  }
  return csv.str();
}

bool EndsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

void SavePlan(const CapturePlan& plan, const PlanCell& cell, const PlanOptions& options, const std::string& json_path,
              const std::string& csv_path) {
  nlohmann::ordered_json j;
  j["format"] = kPlanFormat;
  j["setup"] = SetupName(cell.setup);
  j["options"] = {{"poses", options.poses}, {"goal_mm", options.goal_mm}, {"seed", options.seed},
                  {"candidates", options.candidates}};
  j["noise"] = internal::NoiseJson(cell);
  j["poses"] = nlohmann::ordered_json::array();
  for (const PlannedPose& pose : plan.poses)
    j["poses"].push_back({{"id", pose.id},
                          {"T_base_ee", JsonFromTransform(pose.T_base_ee)},
                          {"cameras", pose.cameras},
                          {"sigma_after", SigmaJson(pose.sigma_after)}});
  j["worst_camera"] = plan.worst_camera;
  j["worst_position_mm"] = plan.worst_position_mm;
  nlohmann::ordered_json limits = nlohmann::ordered_json::object();
  for (const auto& [name, known_mm] : plan.intrinsics_exact_mm)
    limits[name] = {{"intrinsics_exact_mm", known_mm},
                    {"robot_exact_mm", plan.robot_exact_mm.at(name)}};
  if (!limits.empty()) j["sigma_limits"] = limits;
  if (!plan.failure.empty()) j["failure"] = plan.failure;
  if (!csv_path.empty()) {
    const std::string relative =
        std::filesystem::path(csv_path).lexically_relative(std::filesystem::path(json_path).parent_path()).string();
    j["csv"] = relative.empty() ? csv_path : relative;
  }
  WriteFileAtomically(json_path, DumpJson(j));
  if (!csv_path.empty()) WriteFileAtomically(csv_path, PlanCsv(plan));
}

std::vector<PoseRow> ReadPoseFile(const std::string& path) {
  std::string lower = path;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (!EndsWith(lower, ".json")) {
    const std::vector<PoseRow> rows = ReadPoseList(path, PoseListOptions{});
    RequirePlausibleReach(rows, path, LengthUnit::kMetre, "convert it to metres");
    return rows;
  }
  const nlohmann::json json = ReadJsonFile(path);
  const JsonReader root(&json, path);
  root.ExpectObject("a JSON object with \"poses\": [{\"id\", \"T_base_ee\"}, ...]");
  const JsonReader poses = root.Key("poses");
  std::vector<PoseRow> rows;
  std::set<std::string> ids;
  for (std::size_t i = 0; i < poses.ArraySize("a list of poses"); ++i) {
    const JsonReader pose = poses.At(i);
    PoseRow row;
    row.id = pose.Key("id").NonEmptyString("a pose id");
    if (!ids.insert(row.id).second) throw pose.Key("id").Error("expected ids that differ; '" + row.id + "' repeats");
    row.T_base_ee = ReadPose(pose.Key("T_base_ee"), false);
    rows.push_back(row);
  }
  if (rows.empty()) throw poses.Error("expected at least one pose");
  return rows;
}

}  // namespace handeye
