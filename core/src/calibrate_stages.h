// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The stages of Calibrate() (calibrate.cc) and the state they hand on. Each
// stage reads the options and adds its part; one strategy per method
// (calibrate_joint.cc, calibrate_per_camera.cc) solves in between:
//   prepare cameras → prepare views → solve (method) → explain views →
//   fill result → intrinsics check and σ → diagnose.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "handeye/core/calibration.h"
#include "problem.h"
#include "refinement.h"
#include "robot_error.h"

namespace handeye::internal {

/// The estimate: each camera's T_cam_mount and the T_holder_target it uses.
struct Estimate {
  std::vector<std::optional<Eigen::Isometry3d>> T_cam_mount;
  std::vector<Eigen::Isometry3d> T_holder_target;  // per camera
  Eigen::Isometry3d shared_T_holder_target = Eigen::Isometry3d::Identity();
  bool per_camera_target = false;

  /// Per camera, the T_holder_target its views use.
  TargetPoses Targets() const {
    return per_camera_target ? TargetPoses(T_holder_target)
                             : TargetPoses(T_cam_mount.size(), shared_T_holder_target);
  }
};

/// Per camera (tangent of T_cam_mount): the covariance, and where the held
/// given intrinsics at what the views and their prior say would move it
/// (Refinement::T_cam_mount_intrinsics_shift).
/// `from_intrinsics`: the part of `covariance` their uncertainty adds;
/// `with_target`: against T_holder_target's tangent, without that part.
struct CameraCovariance {
  std::map<size_t, Eigen::Matrix<double, 6, 6>> covariance, from_intrinsics, with_target;
  std::map<size_t, Eigen::Matrix<double, 6, 1>> intrinsics_shift;
  /// The part of it the camera's own fx, fy, cx, cy make, a column each
  /// (Refinement::T_cam_mount_own_intrinsics_shift).
  std::map<size_t, Eigen::Matrix<double, 6, 4>> own_intrinsics_shift;
  /// Its δc (Refinement::intrinsics_offset_px).
  std::map<size_t, Eigen::Vector4d> intrinsics_offset;
  void Add(const Refinement& computed, size_t k) {
    if (!computed.T_cam_mount_covariance[k]) return;
    covariance[k] = *computed.T_cam_mount_covariance[k];
    from_intrinsics[k] =
        computed.T_cam_mount_intrinsics_covariance[k].value_or(Eigen::Matrix<double, 6, 6>::Zero());
    if (computed.T_cam_mount_intrinsics_shift[k])
      intrinsics_shift[k] = *computed.T_cam_mount_intrinsics_shift[k];
    if (k < computed.T_cam_mount_own_intrinsics_shift.size() &&
        computed.T_cam_mount_own_intrinsics_shift[k])
      own_intrinsics_shift[k] = *computed.T_cam_mount_own_intrinsics_shift[k];
    if (k < computed.intrinsics_offset_px.size() && computed.intrinsics_offset_px[k])
      intrinsics_offset[k] = *computed.intrinsics_offset_px[k];
    if (k < computed.T_cam_mount_target_covariance.size() &&
        computed.T_cam_mount_target_covariance[k])
      with_target[k] = *computed.T_cam_mount_target_covariance[k];
  }
};

/// What the stages of one calibration hand on. `dataset` and `options` are
/// read, never changed; `working` holds the cameras as the solver sees them
/// (intrinsics estimated where the dataset gives none, refined where asked),
/// and `problem` points into it, so a Calibration is never copied or moved.
struct Calibration {
  Calibration(const Dataset& given, const CalibrationOptions& calibration_options)
      : dataset(given), options(calibration_options), working(given) {}
  Calibration(const Calibration&) = delete;
  Calibration& operator=(const Calibration&) = delete;

  const Dataset& dataset;
  const CalibrationOptions& options;
  Dataset working;
  std::vector<bool> estimated;        ///< per camera: intrinsics estimated from its views
  std::vector<Camera> start_cameras;  ///< the cameras before any refinement
  Problem problem;
  Estimate est;
  std::vector<std::vector<int>> free_intrinsics;  ///< the joint solve's, by camera
  /// The joint solve's robot model as chosen by held-out poses, and whether
  /// that choice holds the robot poses exact (RobotForRound reads it).
  std::optional<ModelChoice> model_choice;
  bool exact_robot = false;
  /// Where the views suggested the robot's error but the exact robot was
  /// taken: that model, whose σ the solution's covariance carries.
  std::optional<RobotPrior> considered_robot;
  /// That model was solved with the given intrinsics found off free
  /// (RobotWithFoundIntrinsicsFree).
  bool considered_intrinsics_free = false;
  /// The robot's error the solution's covariance carries: the joint solve's
  /// model where it modelled the robot, or where the poses were taken as
  /// exact, ConsideredRobot's (none where that is beyond any robot's).
  std::optional<RobotPrior> covariance_robot;
  std::map<size_t, IntrinsicsResult> refined_intrinsics;
  CameraCovariance camera_covariance;
  std::vector<CameraResult::CrossValidation> camera_validation;
  CalibrationResult result;
};

/// `options` with the robust loss at `scale_px`: what one round of a robust solve runs with.
CalibrationOptions AtLossScale(const CalibrationOptions& options, double scale_px);

/// For each camera, the groups the intrinsics check looks at: focal length
/// and principal point, less those the joint solve refines (parameter
/// indices in `free_intrinsics`: 0 fx, 2 cx).
std::vector<unsigned> UnrefinedIntrinsics(const std::vector<std::vector<int>>& free_intrinsics,
                                          size_t num_cameras);

/// The stages before the strategy: the cameras as the solver sees them
/// (intrinsics estimated where none are given; c->estimated, c->start_cameras),
/// then the views (c->problem: PnP, setup checks, robot-motion vote). They
/// throw InputError / SolveError where the data cannot be calibrated.
void PrepareCameras(Calibration* c);
void PrepareViews(Calibration* c);

/// The stages after it: the views and robot records explained (warnings,
/// the pairs of the methods without pair parameters), the result's views and
/// cameras filled, then the intrinsics check and each camera's σ.
void ExplainViews(Calibration* c);
void FillResultStage(Calibration* c);
void IntrinsicsCheckAndSigma(Calibration* c);

/// The strategies: each leaves c->est, c->result.solver and c->camera_covariance
/// set (and, for the joint solve, the robot model, intrinsics and pairs).
void SolveJointMethod(Calibration* c);
void SolvePerCameraMethod(Calibration* c);
void SolveClosedFormMethod(Calibration* c);

}  // namespace handeye::internal
