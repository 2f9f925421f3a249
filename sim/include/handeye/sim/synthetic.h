// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Synthetic workcells with ground truth: camera rings, robot poses and the
/// true projections of the target, without images (render.h draws them).
/// Used by `handeye simulate`, by solver tests (projected observations) and by
/// the benchmarks.

#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "handeye/core/calibration.h"
#include "handeye/core/dataset.h"

namespace handeye {

/// What to simulate. Presets set geometry and cameras; explicit fields override.
struct SceneOptions {
  /// "small" (≈ 6 m², cameras ≈ 1.5 m from the target), "medium" (≈ 12 m²,
  /// ≈ 2.5 m), "large" (≈ 20 m², ≈ 4 m), or "metric-medium" (METRIC's synthetic
  /// medium cell: 4 cameras, 1920×1080, fx = fy = 1371.02, cx = 960.5,
  /// cy = 540.5, no distortion, ≈ 2.3 m from the base, ≈ 1.15 m high).
  std::string cell = "medium";
  Setup setup = Setup::kEyeToHand;
  int num_cameras = 4;
  int num_poses = 20;
  std::uint64_t seed = 1;
  /// Image size; 0 = the preset's (1920×1080).
  int width = 0, height = 0;
  /// Give each camera its own lens distortion (ignored by metric-medium).
  bool distortion = true;
  /// Robot pose noise added to the reported T_base_ee (the truth is kept in
  /// GroundTruth::PoseTruth): translation σ per axis (mm); rotation a turn of
  /// N(0, pose_noise_deg) degrees about a uniformly random axis (σ per axis
  /// pose_noise_deg / √3).
  double pose_noise_mm = 0.0;
  double pose_noise_deg = 0.0;
  /// Exchange the robot records of this many disjoint pairs of poses after the
  /// scene is built (a logging fault: each image then carries another pose's
  /// T_base_ee). The truth keeps the true poses; SyntheticScene lists the pairs.
  int swap_poses = 0;
  /// Non-zero: the robot poses (and their noise) come from this seed while
  /// the cameras and the target come from `seed` — a later capture session
  /// of the same cell.
  std::uint64_t pose_seed = 0;
  /// A camera knocked since calibration (empty: none): its true pose is moved
  /// by bump_mm along its own x axis and turned by bump_deg about its own y axis.
  std::string bumped_camera;
  double bump_mm = 0.0, bump_deg = 0.0;
  /// A point counts as visible when it projects at least this far inside the image.
  double border_margin_px = 4.0;
  /// Non-empty: these true T_base_ee, in this order, instead of the
  /// sampler's (a plan to check end to end); num_poses must equal their
  /// number. Each is kept even when no camera sees the target from it.
  std::vector<Eigen::Isometry3d> given_poses;

  /// False, with the reason in `*why`, for an unknown cell or a value out of
  /// its domain. MakeScene() checks too.
  bool Check(std::string* why) const;
};

/// A simulated cell: the dataset as a user would have it (reported poses,
/// no images yet, no observations) and the truth behind it.
struct SyntheticScene {
  Dataset dataset;
  GroundTruth truth;  ///< with PoseTruth::points_px of every visible point
  /// Pose ids whose robot records were exchanged (SceneOptions::swap_poses).
  std::vector<std::pair<std::string, std::string>> swapped_poses;
};

/// Builds a scene. Deterministic for a given seed. The target is given so any
/// target type can be simulated.
SyntheticScene MakeScene(const SceneOptions& options, std::shared_ptr<const Target> target);

/// T_cam_target of camera `camera` at pose `pose_index` under the truth.
Eigen::Isometry3d TrueCameraFromTarget(const SyntheticScene& scene, int camera, int pose_index);

/// Observations from the true projections plus isotropic Gaussian pixel noise
/// of σ `noise_px` (no images). Fills scene->dataset.observations.
void AddProjectedObservations(SyntheticScene* scene, double noise_px, std::mt19937_64* rng);

/// How honest the result's σ is over simulated scenes (projected observations
/// of a 7×4 checkerboard of 40 mm): for seeds first_seed … first_seed +
/// seeds − 1 of `scene`, each camera's true position and rotation error
/// against 2σ of the joint solve with default options.
struct SigmaCoverage {
  int scenes = 0, cameras = 0;
  int position_within_2sigma = 0, rotation_within_2sigma = 0;
  std::vector<double> position_error_mm, position_sigma_mm;  ///< per camera
  /// Per scene: the robot pose error σ the solve modelled (0: none).
  std::vector<double> robot_sigma_mm, robot_sigma_deg;
  std::vector<std::string> failures;  ///< scenes that did not solve, and why
};
SigmaCoverage MeasureSigmaCoverage(SceneOptions scene, double noise_px, int seeds, std::uint64_t first_seed,
                                   const CalibrationOptions& calibration = CalibrationOptions{});
/// Adds one solved scene's cameras to `coverage` (its `scenes` too).
void AddToCoverage(const CalibrationResult& result, const GroundTruth& truth, SigmaCoverage* coverage);

}  // namespace handeye
