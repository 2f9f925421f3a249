// SPDX-License-Identifier: GPL-2.0-or-later
// The planning view of a simulated cell (sim/plan_cell.h).
#include "handeye/sim/plan_cell.h"

#include <random>

#include "handeye/core/transform.h"

namespace handeye {
namespace {

/// T moved by an error of 1σ `position_m` per axis and turned by 1σ `rotation_rad` about a random axis.
Eigen::Isometry3d Perturbed(const Eigen::Isometry3d& T, double position_m, double rotation_rad,
                            std::mt19937_64* rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Vector3d shift(normal(*rng), normal(*rng), normal(*rng));
  const Eigen::Vector3d turn(normal(*rng), normal(*rng), normal(*rng));
  Eigen::Isometry3d out = T;
  out.translation() += position_m * shift;
  out.linear() = MatrixFromRotationVector(rotation_rad / std::sqrt(3.0) * turn) * T.linear();
  return out;
}

}  // namespace

PlanCell PlanCellOfScene(const SyntheticScene& scene, const RoughKnowledge& rough) {
  std::mt19937_64 rng(rough.seed);
  const double position_m = rough.position_mm / 1000.0, rotation_rad = rough.rotation_deg * M_PI / 180.0;
  PlanCell cell;
  cell.setup = scene.dataset.setup;
  cell.target = scene.dataset.target;
  for (const Camera& camera : scene.dataset.cameras) {
    PlanCamera planned;
    planned.camera = camera;
    planned.T_mount_cam = Perturbed(scene.truth.T_cam.at(camera.name), position_m, rotation_rad, &rng);
    planned.position_sigma_m = position_m;
    planned.rotation_sigma_rad = rotation_rad;
    cell.cameras.push_back(planned);
  }
  cell.T_holder_target = Perturbed(scene.truth.T_target, position_m, rotation_rad, &rng);
  cell.target_position_sigma_m = position_m;
  cell.target_rotation_sigma_rad = rotation_rad;
  cell.pixel_sigma_px = rough.pixel_sigma_px;
  cell.robot_sigma_mm = rough.robot_sigma_mm;
  cell.robot_sigma_deg = rough.robot_sigma_deg;
  // The simulator's flange positions (synthetic.cc): a shell of radius
  // 0.25–1.05 m around the base from 0.3 to 1.9 m high; its target centres
  // lie within 0.4–0.9 m and 0.7–1.5 m high, which this box holds.
  cell.region.box = scene.dataset.setup == Setup::kEyeToHand
                        ? Eigen::AlignedBox3d(Eigen::Vector3d(-0.9, -0.9, 0.6), Eigen::Vector3d(0.9, 0.9, 1.5))
                        : Eigen::AlignedBox3d(Eigen::Vector3d(-1.0, -1.0, 0.6), Eigen::Vector3d(1.0, 1.0, 1.7));
  return cell;
}

}  // namespace handeye
