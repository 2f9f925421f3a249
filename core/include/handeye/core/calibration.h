// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Hand-eye calibration of a camera network (SPEC §3, the paper's method).
///
/// Both setups share one chain (handeye/core/setup_frames.h): the cameras are
/// fixed to the `mount`, the target to the `holder`, and for camera k at robot pose j
///   T_camk_target[j] = T_camk_mount · T_mount_holder[j] · T_holder_target,
///  - eye_to_hand: mount = base, holder = ee,   T_mount_holder[j] = T_base_ee[j];
///  - eye_in_hand: mount = ee,   holder = base, T_mount_holder[j] = T_ee_base[j].
/// The paper's X_k, M_j, Z are T_camk_mount, T_mount_holder[j], T_holder_target.
/// The result reports T_mount_cam (T_base_cam / T_ee_cam, the inverse users
/// want) as CameraResult::T_cam and T_holder_target as CalibrationResult::T_target.

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "handeye/core/dataset.h"
#include "handeye/core/warning.h"

namespace handeye {

/// SPEC §7 `--method`.
enum class Method {
  kJoint,      ///< the paper: one shared T_holder_target, camera-to-camera terms, Cauchy loss
  kPerCamera,  ///< the same reprojection solve, one T_holder_target per camera (Evangelista et al.)
  kTsai, kPark, kHoraud, kAndreff, kDaniilidis,  ///< OpenCV calibrateHandEye, per camera
  kShah, kLi,  ///< OpenCV calibrateRobotWorldHandEye, per camera
  /// ViSP vpHandEyeCalibration, per camera (also one of the initialisation's
  /// candidates for every reprojection method). ViSP 3.5 always prints, so
  /// while any thread is in that call std::cout's buffer and C's `stdout`
  /// stream are swapped for sinks (the first call in swaps them, the last out
  /// puts them back): what other threads print through std::cout or stdout
  /// meanwhile is lost. File descriptor 1 is never touched.
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

/// How far off the given intrinsics may be (1σ): inputs of the calibration
/// that are uncertain themselves. The solve holds the given values (unless
/// refined); every camera's σ carries what this uncertainty moves it by.
/// Defaults are what a factory calibration or an earlier one of the same
/// camera is commonly good to: the focal length within about 1 %, the
/// principal point within a few pixels. 0 takes the group as exact.
struct GivenIntrinsicsSigma {
  /// Focal length, % of the given fx and fy; one error shared by both
  /// (fx = f / pixel pitch x, fy = f / pixel pitch y: a calibration errs in f,
  /// the sensor's aspect ratio is fixed).
  double focal_percent = 1.0;
  /// Principal point, pixels per axis (cx and cy independent).
  double principal_point_px = 3.0;
};
/// Parses `--intrinsics-sigma`: a comma-separated list of `focal=P%` and
/// `principal_point=Npx` (each optional: an item left out keeps its default
/// from `defaults`), or `0` (both exact). Nullopt with the reason in *why.
std::optional<GivenIntrinsicsSigma> ParseIntrinsicsSigma(const std::string& text, std::string* why,
                                                         const GivenIntrinsicsSigma& defaults = {});
/// The `--intrinsics-sigma` text of `sigma`, e.g. "focal=1%,principal_point=3px".
std::string IntrinsicsSigmaText(const GivenIntrinsicsSigma& sigma);

/// When a calibration deserves a warning (Calibrate() adds them to the
/// result's `warnings`; the report shows them). 0 switches a check off.
struct QualityThresholds {
  /// A camera with fewer used views is flagged: hand-eye needs two motions
  /// with non-parallel axes in theory, but with fewer than about ten poses a
  /// single bad pose moves the result visibly (Tsai & Lenz 1989 recommend
  /// well over the minimum).
  int min_views_per_camera = 10;
  /// Robot rotation diversity of one camera's views: the largest rotation
  /// between two of its poses (degrees) below which it is flagged. Tsai and
  /// Lenz show the translation error grows roughly as 1/(rotation angle)
  /// between poses; below 20° it is 3× that of a 60° spread.
  double min_rotation_spread_deg = 20.0;
  /// The largest angle between the rotation axes of two of its relative
  /// motions (degrees, axes folded into [0°, 90°]) below which it is flagged:
  /// the rotation error grows like 1/sin(axis angle), 2× at 30°.
  double min_axis_spread_deg = 30.0;
  /// A camera whose RMS reprojection error through the calibrated chain
  /// exceeds this (pixels) is flagged: corner detectors reach 0.1–0.3 px, so
  /// more than 1 px means a model, robot or detection problem.
  double max_camera_rms_px = 1.0;
  /// Disagreement with the per-camera closed form (CameraResult::closed_form),
  /// pixels: the mean displacement of the camera's target points (placed by
  /// the result's chain) when seen from the closed form's camera pose instead
  /// of the result's. A closed form's error lies mostly along what the images
  /// barely constrain (the camera turning about the target), so millimetres
  /// and degrees would flag good results; the displacement is what the data
  /// can see. In simulated cells with realistic robot noise (0.5–1 mm,
  /// 0.05–0.1°) it stays below 1 px while the closed form is off by up to
  /// 9 mm and 0.2°; a wrong solution (another local minimum, a camera moved
  /// during the session) moves points by tens.
  double max_closed_form_disagreement_px = 5.0;
};

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
  /// Look for the usual setup mistakes before the solve (robot poses inverted
  /// or in another order or unit, rotations transposed, the setup swapped,
  /// the target's size off, images repeated or shifted against the poses) and,
  /// after it, a robot error larger than any real robot's: each is a SolveError
  /// that names the mistake and its fix. False (`--accept-setup`): the data
  /// are taken as they are.
  bool check_setup = true;
  int max_iterations = 200;
  /// The solve has converged when no camera, target or pair pose moves by
  /// more than these in an iteration (or Ceres' own tolerances are met).
  double step_tolerance_mm = 1e-4;
  double step_tolerance_deg = 1e-5;
  /// Threads for Ceres, the setup checks' closed forms and the closed-form
  /// comparison of every camera.
  int threads = 1;
  /// IntrinsicsGroup flags: those intrinsics of every camera become unknowns
  /// of the joint solve, started from the given values (joint method only).
  /// Cameras without intrinsics have all of them estimated whatever this says.
  unsigned refine_intrinsics = kNoIntrinsics;
  /// Uncertainty of the given intrinsics that are not refined, carried into
  /// every calibrated camera's σ (every method; SPEC §6).
  GivenIntrinsicsSigma intrinsics_sigma;
  /// Cameras held at these poses (name → T_cam: T_base_cam or T_ee_cam), e.g.
  /// those a `handeye check` found unmoved: only the others are solved, with
  /// the target transform (joint method only).
  std::map<std::string, Eigen::Isometry3d> fixed_cameras;
  /// Held-out validation (joint method): leave each robot pose out in turn,
  /// solve again from the solution, and predict that pose's views.
  bool cross_validate = false;
  /// After the solve, check each camera's focal length and principal point
  /// against what its views say, and warn when they disagree (intrinsics not refined).
  bool check_intrinsics = true;
  /// After the solve, compare each camera with a per-camera closed form
  /// (Park & Martin; Tsai & Lenz when the method is Park) on the same views.
  bool compare_closed_form = true;
  /// When the result is worth a warning.
  QualityThresholds warn;

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
  /// Its corners were numbered with a 180°-ambiguous board turned half a turn
  /// (cols + rows even: no detector can tell); the robot-motion vote found the
  /// view fits only numbered the other way round (id → N − 1 − id), and the
  /// solve used it so.
  bool flipped = false;
};

/// How well a pose is known (1σ), from the covariance of the solution scaled
/// by the residuals actually seen; with the robot's error modelled, under the
/// error its solved poses show; with what the given intrinsics' own
/// uncertainty moves it by (CalibrationOptions::intrinsics_sigma); for a
/// camera whose given intrinsics the check finds off, with the shift they
/// cause added too (see the warning).
struct PoseUncertainty {
  /// sqrt of the trace of the position's 3×3 covariance, mm: the RMS of the
  /// position error over the three axes together.
  double position_mm = 0;
  /// The same for the orientation (rotation vector of the error, in the
  /// parent frame), degrees.
  double rotation_deg = 0;
  /// Covariance of (x, y, z in mm; rx, ry, rz in deg), in the parent frame.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  /// The part of `covariance` the given intrinsics' own uncertainty adds
  /// (CalibrationOptions::intrinsics_sigma): an error a camera keeps as long
  /// as its intrinsics are the same, so `check` leaves it out (the new views
  /// carry it too).
  Eigen::Matrix<double, 6, 6> from_given_intrinsics = Eigen::Matrix<double, 6, 6>::Zero();
  /// A camera of the joint solve: the covariance of this pose's (x, y, z mm;
  /// rx, ry, rz deg) with the target transform's (`T_target`, the same
  /// units), without what the given intrinsics add. `check` holds the target
  /// as calibrated, and an error of it moves the new estimate much as it
  /// moved this one: their difference is not as uncertain as the two apart.
  std::optional<Eigen::Matrix<double, 6, 6>> covariance_with_target;
  /// position_mm and rotation_deg without `from_given_intrinsics`: how far
  /// the views themselves leave the camera free.
  double OwnPositionMm() const;
  double OwnRotationDeg() const;
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

/// A camera's result against a per-camera closed form on the same views.
struct ClosedFormComparison {
  std::string method;         ///< the closed form's `--method` name
  bool available = false;     ///< false: it could not solve the camera (see why_not)
  std::string why_not;
  double translation_mm = 0;  ///< |t| between the two T_cam
  double rotation_deg = 0;    ///< angle between the two T_cam
  /// Mean image displacement of the camera's target points (placed by the
  /// result's chain) seen from the closed form's camera pose instead of the
  /// result's (see QualityThresholds::max_closed_form_disagreement_px).
  double displacement_px = 0;
};

/// The paper's AX = ZB check (eq. real_metrics) over a camera's used views:
/// A_j = T_target_cam[j] from PnP on view j alone, B_j = T_holder_mount[j],
/// X = T_cam_mount and Z = T_holder_target⁻¹ of the solution; means over the views.
struct AxzbError {
  /// |t| of A_j·X − Z·B_j, both T_target_mount, the pose of the camera's mount (base for
  /// eye_to_hand, ee for eye_in_hand) in the target frame, mm. Measured in the
  /// target frame it includes the lever arm from the target to the mount's
  /// origin (a rotation error of 0.1° moves a point 2 m away by 3.5 mm).
  double target_frame_mm = 0;
  /// Where view j puts the camera (T_mount_holder[j] · T_holder_target · A_j) against the solution's
  /// T_mount_cam, mm, in the frame the camera is fixed to: the figure to
  /// compare across tools and cells.
  double camera_frame_mm = 0;
  double rotation_deg = 0;  ///< the same in either frame
  int views = 0;            ///< views with a PnP pose that entered the means
};

/// The calibration of one camera.
struct CameraResult {
  std::string name;  ///< Camera::name
  bool calibrated = false;  ///< false: the camera never saw the target (reported, not fatal)
  /// eye_to_hand: T_base_cam; eye_in_hand: T_ee_cam.
  Eigen::Isometry3d T_cam = Eigen::Isometry3d::Identity();
  /// The camera's own T_holder_target for methods that estimate one per camera.
  std::optional<Eigen::Isometry3d> own_T_target;
  double rms_px = 0;       ///< reprojection RMS over the camera's used views, pixels
  int views = 0;           ///< views used
  int views_rejected = 0;
  double max_px = 0;       ///< largest point error over its used views, pixels
  int outliers = 0;        ///< used views down-weighted by the robust loss (ViewResult::outlier)
  AxzbError axzb;
  /// Robot rotation diversity of its used views: the largest rotation between
  /// two of its robot poses, and the largest angle between the axes of two
  /// relative motions of more than 2° (folded into [0°, 90°]), degrees.
  double rotation_spread_deg = 0;
  double axis_spread_deg = 0;
  /// With CalibrationOptions::compare_closed_form, for a calibrated camera.
  std::optional<ClosedFormComparison> closed_form;
  /// With intrinsics refinement (or a camera without intrinsics): the result.
  std::optional<IntrinsicsResult> intrinsics;
  /// 1σ of T_cam, every method (absent when the Jacobian is rank deficient):
  /// the reprojection solve's covariance, with what the given intrinsics'
  /// uncertainty (CalibrationOptions::intrinsics_sigma) moves the camera by;
  /// for a closed form, that of the per-camera reprojection solve from the
  /// same views plus the closed form's distance from it.
  std::optional<PoseUncertainty> sigma;
  /// Where `sigma` holds the given intrinsics as uncertain inputs
  /// (CalibrationOptions::intrinsics_sigma): what the views say the given fx,
  /// fy, cx, cy are off by (their estimate less the given value, pixels; 0
  /// for values refined or without a σ), the shift `sigma` counts: the views
  /// and that prior together, or where the intrinsics check finds a group off
  /// (its warning) the views alone for that group, the others still from both. `advise` expects as
  /// much of it to stay after more views as stands out of the views' noise.
  std::optional<Eigen::Vector4d> given_intrinsics_offset_px;
  /// With CalibrationOptions::cross_validate: leave-one-pose-out figures.
  struct CrossValidation {
    int folds = 0;                 ///< poses left out that this camera saw
    double held_out_rms_px = 0;    ///< RMS of its points at the left-out poses, predicted without them
    double position_spread_mm = 0; ///< RMS over all folds of the move of its centre from the full solve
    double rotation_spread_deg = 0;
  };
  std::optional<CrossValidation> cross_validation;
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
  /// Paper eq. (real_metrics), mean over cameras and views, in the target
  /// frame (AxzbError::target_frame_mm).
  double axzb_translation_mm = 0;
  double axzb_rotation_deg = 0;
  /// The same views in the frame the cameras are fixed to (AxzbError::camera_frame_mm).
  double axzb_camera_translation_mm = 0;
};

/// One robot model the joint solve could use, and how well it predicts the
/// views of robot poses it did not see.
struct ModelCandidate {
  /// "exact robot", "robot error modelled" (the σ the views suggest) or
  /// "robot error modelled at the solved poses' σ"
  std::string name;
  double held_out_rms_px = 0;  ///< RMS of the left-out poses' points, predicted without them
  int points = 0;              ///< points predicted (the same for every candidate)
  /// The robot's pose error this candidate assumes, σ per axis (0 for the
  /// exact robot): where the exact poses are chosen, `check` still counts
  /// the first model's error in new poses.
  double robot_sigma_mm = 0;
  double robot_sigma_deg = 0;
};

/// Which robot model the joint solve used and why: where the views suggest
/// the robot's own pose error, the solve with it, the one with exact poses
/// and (where they differ) the one under the σ the solved poses show each
/// predict the views of every fold of poses from the other folds; the model
/// the views suggested is kept unless another candidate predicts more than
/// 5 % better; then the one under the solved poses' σ where it predicts within
/// 5 % of the best, else the one that predicts best.
struct ModelChoice {
  std::string chosen;  ///< a candidate's name
  int folds = 0;       ///< folds over the robot poses
  std::vector<ModelCandidate> candidates;
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
  /// The robot pose error modelled (σ per axis: the prior the solve weighs the
  /// records with), 0 when the poses were taken as exact.
  double robot_sigma_mm = 0;
  double robot_sigma_deg = 0;
  /// The robot pose error the cameras' sigma assumes (σ per axis): the spread
  /// of the solved pose blocks about the solution, times the share of the
  /// records' degrees of freedom the solved unknowns took (the notes say
  /// both); 0 when the poses were taken as exact. `check` and `advise` take
  /// it for new poses: the prior is estimated wide on purpose (on rendered
  /// cells with a robot of 0.1 mm per axis, 0.09-0.26 mm where this was
  /// 0.11-0.12 mm).
  double robot_sigma_solved_mm = 0;
  double robot_sigma_solved_deg = 0;
  /// Set when the robot model was chosen by held-out poses (the default,
  /// --robot-sigma-mm not given, once the views suggest a robot error).
  std::optional<ModelChoice> model;
};

/// Everything a calibration produced. A plain value; frames and units as in
/// SPEC §2 (metres, OpenCV optical camera frames).
struct CalibrationResult {
  Setup setup = Setup::kEyeToHand;
  Method method = Method::kJoint;
  std::vector<CameraResult> cameras;  ///< dataset order
  /// eye_to_hand: T_ee_target; eye_in_hand: T_base_target.
  Eigen::Isometry3d T_target = Eigen::Isometry3d::Identity();
  /// 1σ of T_target (joint method).
  std::optional<PoseUncertainty> target_sigma;
  std::vector<CameraPairResult> camera_pairs;  ///< every pair that shared a pose
  CalibrationMetrics metrics;
  SolverSummary solver;
  std::vector<ViewResult> views;  ///< every observation, used or rejected
  /// Things a user must see (rejected views, uncalibrated cameras, …), each
  /// with its kind and the camera, pose and view it is about.
  std::vector<Warning> warnings;
  /// How the solve went (initialisation chosen, …): information, not a problem.
  std::vector<std::string> notes;
  /// The options the result was computed with (thresholds and loss scale as
  /// given; SolverSummary has the scale used).
  CalibrationOptions options;
  /// Where the result came from: the handeye version that computed it, and
  /// the input file (set by the program that read it; empty in memory).
  std::string handeye_version;
  std::string input;

  /// Frame-explicit readings of `cameras[].T_cam` and `T_target`, which mean
  /// different frames by setup: eye_to_hand has T_base_cam(name) and
  /// T_ee_target(), eye_in_hand T_ee_cam(name) and T_base_target(). Asking
  /// for the other setup's frame throws std::logic_error naming the one to
  /// use; a camera the result does not have, or did not calibrate, throws
  /// std::out_of_range.
  Eigen::Isometry3d T_base_cam(const std::string& camera) const;
  Eigen::Isometry3d T_ee_cam(const std::string& camera) const;
  Eigen::Isometry3d T_ee_target() const;
  Eigen::Isometry3d T_base_target() const;
  /// Camera `camera` in the base frame with the robot at `T_base_ee`, in
  /// either setup: T_base_cam (eye_to_hand: the robot does not move it) or
  /// T_base_ee · T_ee_cam (eye_in_hand).
  Eigen::Isometry3d T_base_cam_at(const std::string& camera,
                                  const Eigen::Isometry3d& T_base_ee) const;
};

/// Calibrates from the dataset's observations (detect first for images).
/// Reentrant: calls may run at the same time, and nothing is written to
/// standard output (for Method::kVisp see its note).
/// Throws InputError for inconsistent input and SolveError when the problem
/// cannot be solved (too few views, degenerate motion, a failed solve). A
/// solve that hits the iteration limit is returned with a warning.
CalibrationResult Calibrate(const Dataset& dataset, const CalibrationOptions& options);

}  // namespace handeye
