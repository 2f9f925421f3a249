// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The calibration problem as the solver sees it: the views (PnP each), the
// measures on them, and the robot's error model; what every stage of the
// engine reads.

#include <ceres/manifold.h>
#include <ceres/product_manifold.h>

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
}  // namespace ceres

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
  std::vector<Eigen::Vector3d> p_target;          ///< target points of the detected ids
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
  std::vector<View> views;                        ///< every observation
  std::vector<std::vector<int>> camera_views;     ///< used view indices per camera
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

/// Per camera: the T_holder_target its views use (joint: the shared one for every camera).
using TargetPoses = std::vector<Eigen::Isometry3d>;

/// σ (pixels, per image axis) of the reprojection residuals of the used
/// views, from their median (robust to a few bad points).
double ResidualSigmaPx(const Problem& problem,
                       const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                       const TargetPoses& T_holder_target);

/// Chordal L2 mean of rotations and mean of translations.
Eigen::Isometry3d MeanTransform(const std::vector<Eigen::Isometry3d>& transforms);

/// Median over used views of the per-view RMS reprojection error for (T_cam_mount,
/// T_holder_target).
double MedianViewRms(const Problem& problem,
                     const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                     const Eigen::Isometry3d& T_holder_target);

/// Reprojection errors (pixels) of one view's points through
/// T_cam_mount · T_mount_holder[j] · T_holder_target.
std::vector<double> ViewErrors(const Problem& problem, const View& view,
                               const Eigen::Isometry3d& T_cam_mount,
                               const Eigen::Isometry3d& T_holder_target);

/// The uncertainty of pose P = T (or T⁻¹ with `invert`) from the
/// tangent-space covariance of the pose block T (PoseManifold).
PoseUncertainty UncertaintyOf(const Eigen::Isometry3d& T,
                              const Eigen::Matrix<double, 6, 6>& tangent_covariance, bool invert);

/// Detection noise σ per image axis (pixels): the median over used views of
/// what their PnP fit leaves (2n − 6 degrees of freedom for n points).
double DetectionSigmaPx(const Problem& problem);

/// The factor that turns a covariance from Ceres (unit residuals) into one
/// of the residuals actually seen: the a posteriori variance factor (2·cost
/// over residuals minus free parameters) times the view design factor, how
/// much an error shared by the points of a view (a robot pose error not
/// modelled, a view's blur) inflates the variance: 1 for independent points,
/// up to the points per view when all move together (from the view blocks'
/// residuals).
double VarianceFactor(ceres::Problem* problem, const std::vector<ceres::ResidualBlockId>& views);

/// Re-runs PnP of every used view with the problem's (refined) intrinsics.
void RecomputePnp(Problem* problem, double max_rms_px);

/// RMS of a view's point errors (pixels), and the largest in *max_error (may be null).
double ViewRms(const std::vector<double>& errors, double* max_error = nullptr);

/// The robot's own pose error, when the joint solve models it: one pose block
/// per robot pose, tied to the reported pose by a prior of these σ.
struct RobotPrior {
  double sigma_m = 0;         ///< flange translation σ per axis, metres
  double sigma_rad = 0;       ///< rotation σ per axis (about the flange, base frame)
  double pixel_sigma_px = 0;  ///< detection noise σ per image axis, the pixel residuals' weight
  double chain_to_pnp =
      0;  ///< median view RMS through the exact-robot chain over PnP's (estimated priors)
  /// The robot's error as the solved pose blocks show it (SettleRobotSigma),
  /// which the covariance of the solution assumes; 0: sigma_m and sigma_rad.
  /// The solve keeps its weights: on METRIC as published, solving under the
  /// settled σ moved the cameras 0.16 mm further from the ground truth.
  double settled_sigma_m = 0;
  double settled_sigma_rad = 0;
};

}  // namespace handeye::internal
