// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A simulated cell with projected observations and the solver's problem
// built on it (core/src/problem.h), with the truth in the solver's frames:
// for the tests of core's internal pieces (test_core, core/src on its path).

#include <cmath>
#include <cstdint>

#include "handeye/core/transform.h"
#include "problem.h"
#include "support/projected_scene.h"

namespace handeye::test {

/// The scene and internal::BuildProblem of it (which points into the scene:
/// not copied, not moved).
struct ProblemCell {
  ProblemCell(const SceneOptions& options, double noise_px)
      : scene(ProjectedScene(options, noise_px)),
        problem(internal::BuildProblem(scene.dataset, CalibrationOptions{})) {}
  ProblemCell(const ProblemCell&) = delete;
  ProblemCell& operator=(const ProblemCell&) = delete;

  /// The true T_cam_mount of camera k (eye_to_hand: T_cam_base; eye_in_hand: T_cam_ee).
  Eigen::Isometry3d TrueCamMount(int k) const {
    return scene.truth.T_cam.at(scene.dataset.cameras[k].name).inverse();
  }
  /// The true T_holder_target (eye_to_hand: T_ee_target; eye_in_hand: T_base_target).
  Eigen::Isometry3d TrueHolderTarget() const { return scene.truth.T_target; }
  /// Every camera's true T_cam_mount.
  std::vector<std::optional<Eigen::Isometry3d>> TrueCamMounts() const {
    std::vector<std::optional<Eigen::Isometry3d>> out;
    for (size_t k = 0; k < scene.dataset.cameras.size(); ++k)
      out.push_back(TrueCamMount(static_cast<int>(k)));
    return out;
  }

  SyntheticScene scene;
  internal::Problem problem;
};

/// Scene options of the "small" cell.
inline SceneOptions SmallCell(Setup setup, int cameras, int poses, std::uint64_t seed) {
  SceneOptions options;
  options.cell = "small";
  options.setup = setup;
  options.num_cameras = cameras;
  options.num_poses = poses;
  options.seed = seed;
  return options;
}

/// How far apart two transforms are: their translations (mm; pass
/// T_cam_mount⁻¹ for where a camera is) and their rotations (deg).
inline double PositionMm(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return 1000.0 * (a.translation() - b.translation()).norm();
}
inline double AngleDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return RotationDistance(a.rotation(), b.rotation()) * 180.0 / M_PI;
}

/// The problem's views still used.
inline int UsedViews(const internal::Problem& problem) {
  int used = 0;
  for (const internal::View& view : problem.views) used += view.used ? 1 : 0;
  return used;
}

}  // namespace handeye::test
