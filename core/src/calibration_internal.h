// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Internal pieces of the calibration engine, shared by its .cc files.

#include <ceres/manifold.h>
#include <ceres/product_manifold.h>

#include <functional>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "handeye/core/calibration.h"

namespace ceres {
class CostFunction;
class Problem;
namespace internal {
class ResidualBlock;
}
using ResidualBlockId = internal::ResidualBlock*;
}

namespace handeye::internal {

/// Ceres' manifold of a pose block `[qx qy qz qw tx ty tz]`: the quaternion's
/// 3-dimensional tangent, then the translation.
using PoseManifold =
    ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>;

/// One observation prepared for the solver.
struct View {
  int camera = 0;
  int pose = 0;
  const Observation* observation = nullptr;
  std::vector<Eigen::Vector3d> p_target;  ///< target points of the detected ids
  std::optional<Eigen::Isometry3d> T_cam_target;  ///< PnP
  double pnp_rms_px = 0;
  bool used = true;
  std::string rejected_because;
  /// Excluded for disagreeing with the other views (robot motion vote or
  /// residuals after a solve), as opposed to failing on its own (PnP).
  bool inconsistent = false;
  /// Excluded for being seen too obliquely (SolvePnp): the angle from
  /// face-on, deg; 0 otherwise.
  double oblique_deg = 0;
  /// Numbered with the target turned half a turn about its normal (ids
  /// reversed on a 180°-ambiguous board): p_target and T_cam_target hold the
  /// turned numbering (FlipView).
  bool flipped = false;
};

/// The dataset in the solver's terms: T_mount_holder per pose and the views.
struct Problem {
  const Dataset* dataset = nullptr;
  std::vector<Eigen::Isometry3d> T_mount_holder;  ///< per pose, SetupFrames::MountFromHolder
  std::vector<View> views;                       ///< every observation
  std::vector<std::vector<int>> camera_views;    ///< used view indices per camera
};

/// Builds views, runs PnP per view and drops views whose points fit no plane pose.
Problem BuildProblem(const Dataset& dataset, const CalibrationOptions& options);

/// Views seen more obliquely than this are not used. Their corners are
/// squeezed to a quarter and less across the tilt, so their poses are poor
/// (on a rendered METRIC-like cell the views of 75-80 degrees fitted the
/// robot's motions so badly that the consensus called their robot records
/// wrong, and took a good view with them); OpenCV's sector detector found none
/// beyond 74.4 degrees on METRIC or the rendered cells, the lattice of the
/// checkerboard detector finds them up to 80.
constexpr double kMaxViewAngleDeg = 75.0;

/// Angle (rad) between the target's normal and the ray to the middle of the
/// points `p_target`, with the target at `T_cam_target`: 0 seen face-on, π/2
/// edge-on.
double ViewAngle(const Eigen::Isometry3d& T_cam_target,
                 const std::vector<Eigen::Vector3d>& p_target);

/// Rebuilds problem->camera_views from the views' `used` flags.
void IndexUsedViews(Problem* problem);

/// The robot-motion vote, before any estimate: for two views a, b of one
/// camera, the target's motion seen by the camera (T_cam_target[a] ·
/// T_cam_target[b]⁻¹) and the robot's motion (M_a · M_b⁻¹) are conjugate
/// (T_cam_mount between them), so their rotation angles and screw pitches agree
/// whatever T_cam_mount and T_holder_target are, within what PnP's noise
/// allows each pair. A view that agrees with fewer than half of the
/// camera's other views, where most views agree with most, is excluded: its
/// robot record belongs to another pose, or its image to another time (or,
/// seen very obliquely, its pose is worse than its corners' noise says).
/// On a 180°-ambiguous target the views are first numbered alike
/// (NumberViewsAlike), and a view that still disagrees is numbered the other
/// way round (FlipView): when that agrees with half of the others, it is used so.
/// Returns the number of views excluded.
int RejectInconsistentMotions(Problem* problem);

/// The half turn F of a 180°-ambiguous target (a checkerboard with
/// cols + rows even) about its normal through its centre, which takes point
/// id to point N − 1 − id; nullopt for a target that has none.
std::optional<Eigen::Isometry3d> HalfTurnSymmetry(const Target& target);

/// Numbers `view` the other way round by the half turn F (HalfTurnSymmetry):
/// every p_target becomes F · p_target (its id's partner, N − 1 − id) and
/// T_cam_target becomes T_cam_target · F, so the pixels and the pose stay as
/// seen; `flipped` toggles.
void FlipView(const Eigen::Isometry3d& F, View* view);

/// Numbers every used view of a 180°-ambiguous target alike, by the half
/// turn F (HalfTurnSymmetry): within a camera, each pair of views is numbered
/// alike when their target motion's rotation angle matches the robot's, and
/// the other way round when it matches only with one of them turned (FlipView);
/// the numbering that most pairs agree with is taken. Between cameras, the
/// one under which the views of the poses two cameras share give one
/// camera-to-camera transform. Of the two numberings of the whole set, the
/// one that turns fewer views. Returns the number of views flipped.
int NumberViewsAlike(Problem* problem, const Eigen::Isometry3d& F);

/// Per camera: the T_holder_target its views use (joint: the shared one for every camera).
using TargetPoses = std::vector<Eigen::Isometry3d>;

/// Used views whose RMS through the solution lies far outside the robust
/// distribution of view RMS (per camera where it has five views or more):
/// above max(median + 8·1.4826·MAD, 4·median, 0.5 px).
std::vector<int> ViewsOffTheSolution(const Problem& problem,
                                     const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                                     const TargetPoses& T_holder_target);

/// σ (pixels, per image axis) of the reprojection residuals of the used
/// views, from their median (robust to a few bad points).
double ResidualSigmaPx(const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                       const TargetPoses& T_holder_target);

/// Views excluded as inconsistent that fit the solution with the target turned
/// over (a half turn about an axis in its plane) are a see-through target read
/// from behind, whose mirrored pattern PnP takes for a front view: says so.
void ExplainInconsistentViews(Problem* problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                              const TargetPoses& T_holder_target);

/// One warning per robot pose all of whose views were excluded as
/// inconsistent: the pose record and the images likely do not belong together.
std::vector<Warning> PoseRecordWarnings(const Problem& problem,
                                        const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                                        const TargetPoses& T_holder_target);

/// Throws SolveError when the used views' robot motions cannot determine T_holder_target
/// (fewer than two motions with non-parallel rotation axes, or tiny rotations).
/// `cameras` limits the check to those cameras (empty: all).
void CheckMotionDiversity(const Problem& problem, const std::vector<int>& cameras = {});
/// The same check for one camera, as a value: empty when fine, else why.
std::string MotionDiversityProblem(const Problem& problem, const std::vector<int>& cameras);

/// Chordal L2 mean of rotations and mean of translations.
Eigen::Isometry3d MeanTransform(const std::vector<Eigen::Isometry3d>& transforms);

/// Camera k's T_cam_mount given T_holder_target, from its PnP views (consensus of
/// T_cam_target · T_target_holder · T_holder_mount[j]).
/// (Not a T_cam_target: sim's TrueCameraFromTarget is that.)
std::optional<Eigen::Isometry3d> CameraGivenTarget(const Problem& problem, int camera,
                                                   const Eigen::Isometry3d& T_holder_target);
/// T_holder_target given camera k's T_cam_mount, from its PnP views (consensus of
/// T_holder_mount[j] · T_mount_cam · T_cam_target).
std::optional<Eigen::Isometry3d> TargetGivenCamera(const Problem& problem, int camera,
                                                   const Eigen::Isometry3d& T_cam_mount);

/// Closed-form hand-eye of one camera with a baseline method (tsai … li, visp).
/// Returns (T_cam_mount, T_holder_target) of the camera or nullopt with the reason in *why.
std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> ClosedFormHandEye(
    const Problem& problem, int camera, Method method, std::string* why);

/// One closed-form solution of one camera: the method's name, T_cam_mount, T_holder_target.
struct NamedClosedForm {
  std::string method;
  Eigen::Isometry3d T_cam_mount;
  Eigen::Isometry3d T_holder_target;
};

/// OpenCV's Park and Tsai and ViSP's closed forms on one camera, those that
/// solve: the initialisation candidates of the reprojection solves, which must
/// not print (ViSP's prints are dropped without touching fd 1). Empty with the
/// reason in *why when none solves.
std::vector<NamedClosedForm> SilentClosedForms(const Problem& problem, int camera, std::string* why);

/// The best (median view RMS of the camera) of SilentClosedForms on one camera.
/// `*chosen` names the method kept; nullopt with the reason in *why when none solves.
std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> SilentClosedFormHandEye(
    const Problem& problem, int camera, std::string* chosen, std::string* why);

/// Linear AX = XB over the motions of all cameras at once (shared T_holder_target), for
/// cameras whose own motions are too few for a per-camera solve.
std::optional<Eigen::Isometry3d> SharedTargetClosedForm(const Problem& problem);

/// The same problem with each camera's used views cut to at most
/// `max_views` chosen for diverse robot rotations (farthest-point sampling):
/// closed forms cost far more than linearly in views, and need diversity, not bulk.
Problem WithDiverseViews(const Problem& problem, size_t max_views);

/// Initial T_cam_mount (per camera, nullopt for cameras without views) and
/// T_holder_target for the joint solve.
struct Initialisation {
  std::vector<std::optional<Eigen::Isometry3d>> T_cam_mount;
  Eigen::Isometry3d T_holder_target = Eigen::Isometry3d::Identity();
  std::vector<std::string> notes;
  /// Per camera, the intrinsics (OpenCVCameraModel indices) that are unknowns
  /// of the joint solve, started from the problem's cameras; empty: fixed.
  std::vector<std::vector<int>> free_intrinsics;
  /// The given intrinsics (the prior's centre, see IntrinsicsPrior) and the
  /// pixel σ that weighs the prior against the reprojection residuals.
  std::vector<Camera> given_cameras;
  double pixel_sigma_px = 1.0;
  /// Per camera: its T_cam_mount is held at its start (CalibrationOptions::fixed_cameras).
  std::vector<bool> fixed_T_cam_mount;
  /// With a robot prior: per pose, the start of its block (empty: the reported pose).
  std::vector<std::optional<Eigen::Isometry3d>> T_mount_holder;
};
Initialisation InitialiseJoint(const Problem& problem);

/// Median over used views of the per-view RMS reprojection error for (T_cam_mount, T_holder_target).
double MedianViewRms(const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                     const Eigen::Isometry3d& T_holder_target);

/// Reprojection errors (pixels) of one view's points through
/// T_cam_mount · T_mount_holder[j] · T_holder_target.
std::vector<double> ViewErrors(const Problem& problem, const View& view, const Eigen::Isometry3d& T_cam_mount,
                               const Eigen::Isometry3d& T_holder_target);

/// Output of a nonlinear refinement.
struct Refinement {
  std::vector<std::optional<Eigen::Isometry3d>> T_cam_mount;
  std::vector<Eigen::Isometry3d> T_holder_target;          ///< one (joint) or one per camera (per-camera)
  std::map<std::pair<int, int>, Eigen::Isometry3d> pairs;  ///< (k, t) → T_camk_camt
  SolverSummary summary;
  /// With a robot prior: per pose, the solved robot pose (nullopt for poses without views).
  std::vector<std::optional<Eigen::Isometry3d>> T_mount_holder;
  /// Per camera (joint solve): the intrinsics after the solve.
  std::vector<std::array<double, OpenCVCameraModel::kNumParams>> intrinsics;
  /// JointStep::kCovariance: 1σ of the free intrinsics (scaled by the
  /// residuals seen; 0 for fixed ones, infinite when the views cannot
  /// determine them at all), and the tangent-space covariance of each
  /// T_cam_mount and of T_holder_target (Ceres' quaternion-manifold tangent then translation; empty when
  /// the Jacobian is rank deficient).
  std::vector<std::array<double, OpenCVCameraModel::kNumParams>> intrinsics_sigma;
  std::vector<std::optional<Eigen::Matrix<double, 6, 6>>> T_cam_mount_covariance;
  /// With the covariance: per camera, where its T_cam_mount would be (tangent)
  /// with the held given intrinsics at what their prior and the views together
  /// say (ConsiderCovariance::Shift; zero when they are exact or all refined).
  std::vector<std::optional<Eigen::Matrix<double, 6, 1>>> T_cam_mount_intrinsics_shift;
  /// With the covariance: per camera, the part of T_cam_mount_covariance the
  /// held given intrinsics' uncertainty adds (ConsiderCovariance::Consider).
  std::vector<std::optional<Eigen::Matrix<double, 6, 6>>> T_cam_mount_intrinsics_covariance;
  std::optional<Eigen::Matrix<double, 6, 6>> T_holder_target_covariance;
};

/// The uncertainty of pose P = T (or T⁻¹ with `invert`) from the
/// tangent-space covariance of the pose block T (PoseManifold).
PoseUncertainty UncertaintyOf(const Eigen::Isometry3d& T, const Eigen::Matrix<double, 6, 6>& tangent_covariance,
                              bool invert);

/// Starts the next joint solve from `solved`: its camera transforms (where it
/// has them), its T_holder_target and, with robot pose blocks, their poses.
void WarmStart(const Refinement& solved, Initialisation* init);

/// What RefineJoint does with the problem it builds: solve it, or only
/// compute the covariance of the given values (the solution).
enum class JointStep { kSolve, kCovariance };
/// The robot's own pose error, when the joint solve models it: one pose block
/// per robot pose, tied to the reported pose by a prior of these σ.
struct RobotPrior {
  double sigma_m = 0;         ///< flange translation σ per axis, metres
  double sigma_rad = 0;       ///< rotation σ per axis (about the flange, base frame)
  double pixel_sigma_px = 0;  ///< detection noise σ per image axis, the pixel residuals' weight
  double chain_to_pnp = 0;    ///< median view RMS through the exact-robot chain over PnP's (estimated priors)
  /// The robot's error as the solved pose blocks show it (SettleRobotSigma),
  /// which the covariance of the solution assumes; 0: sigma_m and sigma_rad.
  /// The solve keeps its weights: on METRIC as published, solving under the
  /// settled σ moved the cameras 0.16 mm further from the ground truth.
  double settled_sigma_m = 0;
  double settled_sigma_rad = 0;
};

/// Expectation maximisation of the robot's σ over the solution's pose blocks
/// (`solution`, solved from `init` under `robot`): each step takes every
/// record's correction plus its posterior variance (the views' information
/// about the flange and the prior's) and solves a copy again, until σ moves
/// < 5 % (≤ 4 steps). Sets robot->settled_sigma_m and settled_sigma_rad. The
/// estimate rule (EstimateRobotPrior) errs wide on purpose; this is what the
/// pose blocks say.
void SettleRobotSigma(const Problem& problem, const Initialisation& init,
                      const Refinement& solution, const CalibrationOptions& options,
                      RobotPrior* robot);

/// Detection noise σ per image axis (pixels): the median over used views of
/// what their PnP fit leaves (2n − 6 degrees of freedom for n points).
double DetectionSigmaPx(const Problem& problem);

/// The robot's pose error as the views show it through the chain: nullopt when
/// the residuals through the chain are not clearly above PnP's (over 1.2×;
/// the robot is then as exact as the images can tell); else σ of the flange's
/// displacement across the viewing rays and of its rotation, from the medians
/// of where PnP and the chain put the target, less PnP's own noise there.
std::optional<RobotPrior> EstimateRobotPrior(const Problem& problem,
                                             const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                                             const TargetPoses& T_holder_target);

/// The paper's joint solve: shared T_holder_target, optional c_cross terms; with `robot`,
/// every robot pose is a block of the solve too, under its prior.
Refinement RefineJoint(const Problem& problem, const Initialisation& init,
                       const CalibrationOptions& options, const std::optional<RobotPrior>& robot = std::nullopt,
                       JointStep step = JointStep::kSolve);
/// One T_holder_target per camera, no cross terms (for --method per-camera).
/// JointStep::kCovariance: no solve, each camera's T_cam_mount_covariance at
/// the given values, its given intrinsics uncertain inputs.
Refinement RefinePerCamera(const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                           const std::vector<Eigen::Isometry3d>& T_holder_target, const CalibrationOptions& options,
                           JointStep step = JointStep::kSolve);

/// The intrinsics (OpenCVCameraModel indices) of `camera` that the groups
/// (IntrinsicsGroup flags) make unknowns: distortion is k1, k2, p1, p2 and
/// every further non-zero coefficient, never the tilt.
std::vector<int> FreeIntrinsics(const Camera& camera, unsigned groups);

/// The factor that turns a covariance from Ceres (unit residuals) into one
/// of the residuals actually seen: the a posteriori variance factor (2·cost
/// over residuals minus free parameters) times the view design factor, how
/// much an error shared by the points of a view (a robot pose error not
/// modelled, a view's blur) inflates the variance: 1 for independent points,
/// up to the points per view when all move together (from the view blocks'
/// residuals).
double VarianceFactor(ceres::Problem* problem, const std::vector<ceres::ResidualBlockId>& views);

/// 1σ of the prior of each intrinsic parameter about its given value: the
/// value that moves an image corner by 20 px.
std::array<double, OpenCVCameraModel::kNumParams> IntrinsicsPriorSigma(const Camera& camera);

/// The prior residuals of the free intrinsics about `given`, in the units of
/// pixel residuals of σ `pixel_sigma_px`. Block: the camera's 18 intrinsics.
ceres::CostFunction* IntrinsicsPrior(const Camera& given, const std::vector<int>& free, double pixel_sigma_px);

/// The given intrinsics of a camera that are uncertain inputs of a solve
/// that holds them (ConsiderCovariance): those of fx, fy, cx, cy not in
/// `free` whose group has a σ in `sigma`, ascending, with their covariance
/// (fx and fy share one relative error; cx and cy independent).
struct UncertainIntrinsics {
  std::vector<int> params;
  Eigen::MatrixXd covariance;
};
UncertainIntrinsics UncertainGivenIntrinsics(const Camera& camera, const std::vector<int>& free,
                                             const GivenIntrinsicsSigma& sigma);
/// A prior on `uncertain.params` about the camera's values, weighted as pixel
/// residuals of σ `pixel_sigma_px` (only needs to make the information
/// invertible: ConsiderCovariance does not depend on it). Block: the 18 intrinsics.
ceres::CostFunction* UncertainIntrinsicsPrior(const Camera& camera, const UncertainIntrinsics& uncertain,
                                              double pixel_sigma_px);
/// The information that prior gives `uncertain.params` (diagonal, its units).
Eigen::MatrixXd UncertainIntrinsicsPriorInformation(const UncertainIntrinsics& uncertain, double pixel_sigma_px);
/// `free` and `uncertain.params` together, ascending: a block's tangent
/// coordinates; *uncertain_tangent gets where the uncertain ones are in it.
std::vector<int> IntrinsicsUnknowns(const std::vector<int>& free, const UncertainIntrinsics& uncertain,
                                    std::vector<int>* uncertain_tangent);

/// The free intrinsics the views hardly determine: their 1σ after the solve
/// is more than half their prior's (the prior, not the views, holds them).
std::vector<int> UndeterminedIntrinsics(const Camera& given,
                                        const std::array<double, OpenCVCameraModel::kNumParams>& sigma,
                                        const std::vector<int>& free);

/// Intrinsics of camera `k` estimated from its views alone (closed form from
/// the views' homographies, then OpenCV's calibration: fx, fy, cx, cy, k1,
/// k2, p1, p2), for a camera whose dataset gives none. Throws SolveError with
/// advice when the views are too few or too alike to determine them.
Camera EstimateIntrinsics(const Dataset& dataset, int k);

/// Re-runs PnP of every used view with the problem's (refined) intrinsics.
void RecomputePnp(Problem* problem, double max_rms_px);

/// The check of the given intrinsics after a solve: per camera, fx, fy, cx,
/// cy as the camera's views alone say (its T_cam_mount, its own T_holder_target and
/// those four free); a
/// warning where a group in `check[k]` (kFocal, kPrincipalPoint) differs from
/// the given values by more than 3σ and by a visible amount (0.3 % of the
/// focal length, 0.5 px).
/// With `robot`, each robot pose is a block under that prior, as in the joint solve.
/// With `shift`: per camera warned about, how far the given values of the
/// groups it names move T_cam_mount from where the views' own intrinsics put
/// it (tangent of T_cam_mount, linearised: C_xK C_KK⁻¹ ΔK from the same
/// covariance); a bias the covariance of the joint solve does not hold.
std::vector<Warning> IntrinsicsWarnings(
    const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target, double cauchy_scale_px, const std::vector<unsigned>& check,
    const std::optional<RobotPrior>& robot,
    std::map<size_t, Eigen::Matrix<double, 6, 1>>* shift = nullptr);

/// RMS of a view's point errors (pixels), and the largest in *max_error (may be null).
double ViewRms(const std::vector<double>& errors, double* max_error = nullptr);

/// Per camera, the T_holder_target its views use (one shared, or one per camera).
TargetPoses TargetPosesOf(const Refinement& refined, size_t num_cameras);

/// The nonlinear solve made robust: `solve(scale)` runs one refinement
/// (warm-started by the caller from the last one). After each solve, views far
/// outside the robust residual distribution are excluded and the loss scale is
/// set from the residuals (when not fixed), then it solves again, until
/// nothing changes (at most a few rounds). Warnings go to *warnings.
Refinement RobustSolve(Problem* problem, const CalibrationOptions& options, double first_scale,
                       const std::function<Refinement(double scale_px)>& solve, std::vector<Warning>* warnings);

/// Leave-one-pose-out: for each robot pose with used views, the joint solve
/// without them (from `init`, the solution), its prediction of their points,
/// and how far each camera moved from the full solve. One entry per camera.
void CrossValidate(const Problem& problem, const Initialisation& init, const CalibrationOptions& options,
                   const std::optional<RobotPrior>& robot, std::vector<CameraResult::CrossValidation>* out);

}  // namespace handeye::internal
