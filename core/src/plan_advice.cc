// SPDX-License-Identifier: GPL-2.0-or-later
// Advice after a capture (handeye/core/plan_advice.h).
#include "handeye/core/plan_advice.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "detection_noise.h"

namespace handeye {
namespace {

constexpr double kDeg = M_PI / 180.0;
/// The region a recorded capture shows the robot reaches, grown by this.
constexpr double kRegionGrowthM = 0.1;
constexpr double kTiltGrowthRad = 10.0 * kDeg;
/// The least ± taken for a solved pose (its σ can be tiny).
constexpr double kMinPositionM = 1e-3, kMinRotationRad = 0.05 * kDeg;

/// The detection noise σ (per axis) of each solved camera's views, from
/// their residuals through the calibrated chain, in the order of `cameras`.
std::vector<std::vector<double>> ViewSigmas(const CalibrationResult& result,
                                            const std::vector<PlanCamera>& cameras) {
  std::vector<std::vector<double>> sigmas(cameras.size());
  for (const ViewResult& view : result.views)
    for (size_t k = 0; k < cameras.size(); ++k)
      if (view.used && view.camera == cameras[k].camera.name && view.rms_px > 0)
        sigmas[k].push_back(view.rms_px / std::sqrt(2.0));
  return sigmas;
}

/// Cameras that detect unlike the others, as the solve weighed them
/// (SigmasApart): their own σ, and the cell's that of the others' views.
void CameraNoise(const CalibrationResult& result, PlanCell* cell) {
  const std::vector<std::vector<double>> sigmas = ViewSigmas(result, cell->cameras);
  const std::vector<double> apart = internal::SigmasApart(sigmas);
  std::vector<double> others;
  bool any_apart = false;
  for (size_t k = 0; k < apart.size(); ++k) {
    cell->cameras[k].pixel_sigma_px = apart[k];
    if (apart[k] > 0)
      any_apart = true;
    else
      others.insert(others.end(), sigmas[k].begin(), sigmas[k].end());
  }
  if (any_apart && !others.empty())
    cell->pixel_sigma_px = internal::MedianSigmaPx(std::move(others));
}

/// The region the recorded poses span (see PlanCellOfResult).
PlanRegion RegionOfPoses(const std::vector<PlannedPose>& recorded) {
  PlanRegion region;
  Eigen::AlignedBox3d box;
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  for (const PlannedPose& pose : recorded) {
    box.extend(pose.T_base_ee.translation());
    axis += pose.T_base_ee.linear().col(2);
  }
  if (recorded.empty() || !(axis.norm() > 1e-6)) return region;
  region.box = Eigen::AlignedBox3d(box.min().array() - kRegionGrowthM, box.max().array() + kRegionGrowthM);
  region.tilt_axis = axis.normalized();
  double spread = 0;
  for (const PlannedPose& pose : recorded)
    spread = std::max(spread, std::acos(std::clamp(pose.T_base_ee.linear().col(2).dot(region.tilt_axis), -1.0, 1.0)));
  region.max_tilt_rad = std::min(M_PI, spread + kTiltGrowthRad);
  return region;
}

}  // namespace

std::vector<PlannedPose> RecordedPoses(const Dataset& dataset, const CalibrationResult& result) {
  std::vector<PlannedPose> out;
  for (const RobotPose& pose : dataset.poses) {
    PlannedPose recorded;
    recorded.id = pose.id;
    recorded.T_base_ee = pose.T_base_ee;
    for (const ViewResult& view : result.views)
      if (view.used && view.pose_id == pose.id) recorded.cameras.push_back(view.camera);
    out.push_back(recorded);
  }
  return out;
}

PlanCell PlanCellOfResult(const Dataset& dataset, const CalibrationResult& result,
                          const std::optional<PlanCell>& given) {
  PlanCell cell;
  if (given) cell = *given;
  cell.setup = dataset.setup;
  cell.target = dataset.target;
  cell.cameras.clear();
  double sum_squares = 0;
  int cameras = 0;
  for (size_t k = 0; k < dataset.cameras.size() && k < result.cameras.size(); ++k) {
    const CameraResult& solved = result.cameras[k];
    if (!solved.calibrated) continue;
    PlanCamera camera;
    camera.camera = solved.intrinsics ? solved.intrinsics->camera : dataset.cameras[k];
    camera.T_mount_cam = solved.T_cam;
    // The views' own σ: what the given intrinsics' uncertainty adds moves
    // the camera together with where its image puts the target, so it
    // widens no visibility margin.
    camera.position_sigma_m = std::max(kMinPositionM, solved.sigma ? solved.sigma->OwnPositionMm() / 1000.0 : 0.0);
    camera.rotation_sigma_rad = std::max(kMinRotationRad, solved.sigma ? solved.sigma->OwnRotationDeg() * kDeg : 0.0);
    camera.refine_intrinsics = solved.intrinsics.has_value();
    camera.intrinsics_unknown = camera.refine_intrinsics && !dataset.cameras[k].has_intrinsics;
    if (!camera.refine_intrinsics)
      camera.given_intrinsics_offset_px = solved.given_intrinsics_offset_px;
    cell.cameras.push_back(camera);
    sum_squares += solved.rms_px * solved.rms_px;
    ++cameras;
  }
  cell.T_holder_target = result.T_target;
  cell.target_position_sigma_m = std::max(kMinPositionM, result.target_sigma ? result.target_sigma->position_mm / 1000.0 : 0.0);
  cell.target_rotation_sigma_rad = std::max(kMinRotationRad, result.target_sigma ? result.target_sigma->rotation_deg * kDeg : 0.0);
  if (cameras > 0 && sum_squares > 0) cell.pixel_sigma_px = std::sqrt(sum_squares / cameras / 2.0);
  CameraNoise(result, &cell);
  // The robot's error the σ reported assumes (results written before it: the
  // prior the solve weighed with, wide on purpose).
  const bool solved = result.solver.robot_sigma_solved_mm > 0;
  cell.robot_sigma_mm = solved ? result.solver.robot_sigma_solved_mm : result.solver.robot_sigma_mm;
  cell.robot_sigma_deg =
      solved ? result.solver.robot_sigma_solved_deg : result.solver.robot_sigma_deg;
  cell.intrinsics_sigma = result.options.intrinsics_sigma;  // as the solve weighed them
  cell.cross_terms = result.options.cross_terms;
  if (!given) cell.region = RegionOfPoses(RecordedPoses(dataset, result));
  return cell;
}

Advice Advise(const PlanCell& cell, const std::vector<PlannedPose>& recorded, const PlanOptions& options) {
  Advice advice;
  advice.now = PredictSigmaOfViews(cell, recorded);
  if (options.goal_mm > 0)
    for (const auto& [name, sigma] : advice.now)
      if (sigma.position_mm > options.goal_mm) advice.above_goal.push_back(name);
  advice.next = PlanCapture(cell, options, recorded);
  return advice;
}

}  // namespace handeye
