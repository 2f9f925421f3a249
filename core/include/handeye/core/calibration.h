// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Hand-eye calibration of a camera network (SPEC §3, the paper's method).
///
/// Both setups share one chain, p_cam = X_k · M_j · Z · p_target, with
///  - eye_to_hand: X_k = T_cam_base, M_j = T_base_ee[j], Z = T_ee_target;
///  - eye_in_hand: X_k = T_cam_ee,   M_j = T_ee_base[j], Z = T_base_target.
/// The result reports the inverses users want (T_base_cam / T_ee_cam) and Z.

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "handeye/core/dataset.h"

namespace handeye {

/// SPEC §7 `--method`.
enum class Method {
  kJoint,      ///< the paper: one shared Z, camera-to-camera terms, Cauchy loss
  kPerCamera,  ///< the same reprojection solve, one Z per camera (Evangelista et al.)
  kTsai, kPark, kHoraud, kAndreff, kDaniilidis,  ///< OpenCV calibrateHandEye, per camera
  kShah, kLi,  ///< OpenCV calibrateRobotWorldHandEye, per camera
  /// ViSP vpHandEyeCalibration, per camera. ViSP 3.5 always prints its
  /// residuals to standard output, so Calibrate() points file descriptor 1 at
  /// /dev/null around that call, one call at a time (a process-wide lock):
  /// what other threads write to stdout meanwhile is lost. No other method
  /// touches stdout.
  kVisp,
};
/// The `--method` name of a method, e.g. "joint".
const char* MethodName(Method method);
/// Parses a method name; nullopt if unknown.
std::optional<Method> ParseMethod(const std::string& name);
/// Every method name, in the order of the paper's tables.
std::vector<std::string> MethodNames();

/// Groups of intrinsics the joint solve can refine (SPEC §7 `--refine-intrinsics`), bit flags.
enum IntrinsicsGroup : unsigned {
  kNoIntrinsics = 0,
  kFocal = 1,           ///< fx, fy
  kPrincipalPoint = 2,  ///< cx, cy
  kDistortion = 4,      ///< k1, k2, p1, p2 and every further non-zero coefficient given (not the tilt)
  kAllIntrinsics = 7,
};
/// Parses a comma-separated list of `focal`, `principal_point`, `distortion`,
/// or `all`; nullopt with the reason in *why.
std::optional<unsigned> ParseIntrinsicsGroups(const std::string& list, std::string* why);

/// How Calibrate() solves. Defaults are the paper's method.
struct CalibrationOptions {
  Method method = Method::kJoint;  ///< SPEC §7 `--method`
  /// Scale of the Cauchy loss on every reprojection residual, pixels; 0
  /// (default) sets it from the data: 3 σ of the residuals seen after a first
  /// solve (σ from their median), at least 1 px (the paper's value), so a cell
  /// whose robot adds pixels of error is not solved in the loss's flat tail.
  double cauchy_scale_px = 0.0;
  /// The paper's camera-to-camera terms c_cross (joint method only).
  bool cross_terms = true;
  /// Views whose PnP pose explains the detected points worse than this RMS
  /// (pixels) are dropped before initialisation (corners that fit no plane pose).
  double pnp_max_rms_px = 3.0;
  /// The robot's own pose error, σ per axis of the flange position (mm) and of
  /// its rotation (deg). Negative (default): estimated from the views after a
  /// first solve, and modelled (joint method: one pose block per robot pose
  /// under this prior) only where it shows in the residuals; 0: the robot's
  /// poses are taken as exact (the paper's model). Set both or neither.
  double robot_sigma_mm = -1;
  double robot_sigma_deg = -1;
  /// Views that do not fit the consensus are excluded and named: robot
  /// motions that no other view of the camera agrees with (before the solve),
  /// and views far outside the robust residual distribution after it.
  bool reject_views = true;
  int max_iterations = 200;
  /// The solve has converged when no camera, target or pair pose moves by
  /// more than these in an iteration (or Ceres' own tolerances are met).
  double step_tolerance_mm = 1e-4;
  double step_tolerance_deg = 1e-5;
  /// Threads for Ceres.
  int threads = 1;
  /// IntrinsicsGroup flags: those intrinsics of every camera become unknowns
  /// of the joint solve, started from the given values (joint method only).
  /// Cameras without intrinsics have all of them estimated whatever this says.
  unsigned refine_intrinsics = kNoIntrinsics;
  /// After the solve, check each camera's focal length and principal point
  /// against what its views say, and warn when they disagree (intrinsics not refined).
  bool check_intrinsics = true;

  /// False, with the reason in `*why`, when a value is out of its domain
  /// (negative scale, non-positive iterations or threads, …). Calibrate() checks them
  /// too and throws InputError.
  bool Check(std::string* why) const;
};

/// One view (a camera's image at a robot pose) as the solver saw it.
struct ViewResult {
  std::string pose_id;  ///< RobotPose::id
  std::string camera;   ///< Camera::name
  int num_points = 0;   ///< detected target points in the view
  bool used = true;             ///< false: excluded (see rejected_because)
  std::string rejected_because; ///< why, when not used
  double rms_px = 0;            ///< reprojection through the calibrated chain
  double max_px = 0;            ///< largest point error of the view, pixels
  /// Down-weighted by the robust loss: RMS above 3 Cauchy scales.
  bool outlier = false;
};

/// A camera's intrinsics as the joint solve refined (or estimated) them.
struct IntrinsicsResult {
  /// The refined camera (same name and size; distortion with at least the
  /// coefficients given, 5 when none were), ready to be written back.
  Camera camera;
  /// 1σ of each parameter (OpenCVCameraModel order), scaled by the residuals
  /// seen; 0 for parameters held fixed.
  std::array<double, OpenCVCameraModel::kNumParams> sigma{};
  /// Parameter names (fx, cy, k1, …) that were unknowns of the final solve.
  std::vector<std::string> refined;
  /// Parameters asked for that the views could not determine: held at the given value.
  std::vector<std::string> undetermined;
};

/// The calibration of one camera.
struct CameraResult {
  std::string name;  ///< Camera::name
  bool calibrated = false;  ///< false: the camera never saw the target (reported, not fatal)
  /// eye_to_hand: T_base_cam; eye_in_hand: T_ee_cam.
  Eigen::Isometry3d T_cam = Eigen::Isometry3d::Identity();
  /// The camera's own Z for methods that estimate one per camera.
  std::optional<Eigen::Isometry3d> own_T_target;
  double rms_px = 0;       ///< reprojection RMS over the camera's used views, pixels
  int views = 0;           ///< views used
  int views_rejected = 0;
  /// With intrinsics refinement (or a camera without intrinsics): the result.
  std::optional<IntrinsicsResult> intrinsics;
};

/// T_camk_camt of a pair of cameras that saw the target at the same pose.
struct CameraPairResult {
  std::string camera_k, camera_t;  ///< camera names
  /// Pose of camera t's optical frame in camera k's; metres.
  Eigen::Isometry3d T_camk_camt = Eigen::Isometry3d::Identity();
  int shared_views = 0;  ///< poses at which both saw the target
};

/// Summary errors of a calibration.
struct CalibrationMetrics {
  double rms_px = 0;               ///< all points of all used views
  double axzb_translation_mm = 0;  ///< paper eq. (real_metrics), mean over cameras and views
  double axzb_rotation_deg = 0;
};

/// How the solver ran.
struct SolverSummary {
  double seconds = 0;        ///< wall time of the solve
  int iterations = 0;        ///< Ceres iterations (0 for closed-form methods)
  /// False when the solver stopped at the iteration limit: the result is
  /// written with a warning, not thrown away.
  bool converged = false;
  std::string termination;   ///< Ceres' termination type, or the method's status
  double cauchy_scale_px = 0;  ///< the robust loss scale used (0 for closed forms)
  int rounds = 0;  ///< solves run (each after excluding views off the previous one)
  /// The robot pose error modelled (σ per axis), 0 when the poses were taken as exact.
  double robot_sigma_mm = 0;
  double robot_sigma_deg = 0;
};

/// Everything a calibration produced. A plain value; frames and units as in
/// SPEC §2 (metres, OpenCV optical camera frames).
struct CalibrationResult {
  Setup setup = Setup::kEyeToHand;
  Method method = Method::kJoint;
  std::vector<CameraResult> cameras;  ///< dataset order
  /// eye_to_hand: T_ee_target; eye_in_hand: T_base_target.
  Eigen::Isometry3d T_target = Eigen::Isometry3d::Identity();
  std::vector<CameraPairResult> camera_pairs;  ///< every pair that shared a pose
  CalibrationMetrics metrics;
  SolverSummary solver;
  std::vector<ViewResult> views;  ///< every observation, used or rejected
  /// Things a user must see (rejected views, uncalibrated cameras, …).
  std::vector<std::string> warnings;
  /// How the solve went (initialisation chosen, …): information, not a problem.
  std::vector<std::string> notes;
};

/// Calibrates from the dataset's observations (detect first for images).
/// Reentrant: calls may run at the same time, and nothing is written to
/// standard output (for Method::kVisp see its note).
/// Throws InputError for inconsistent input and SolveError when the problem
/// cannot be solved (too few views, degenerate motion, a failed solve). A
/// solve that hits the iteration limit is returned with a warning.
CalibrationResult Calibrate(const Dataset& dataset, const CalibrationOptions& options);

}  // namespace handeye
