// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Capture planning (`handeye plan`, `handeye advise`): which robot poses to
/// record so that every camera's pose is determined to a goal, chosen before
/// the robot moves from what is roughly known about the cell.
///
/// The predicted σ of a camera is the one the joint solve reports for noise
/// of the given size, the median over that noise (the shift the views
/// suggest for the given intrinsics is a draw of it; see below): the
/// inverse of the Fisher information of the chain
/// T_cam_mount · T_mount_holder[j] · T_holder_target, built from the solver's
/// own cost functions (ViewReprojectionWithRobotError, RobotPosePrior), with
/// every robot pose a block under the robot's error prior (marginalised per
/// pose), the detection noise σ on every target point, and the camera and
/// target intrinsics that are unknowns of the solve (fx, fy, cx, cy of the
/// cameras marked for refinement) as further blocks. The given intrinsics of
/// the other cameras are uncertain inputs as in the solve
/// (CalibrationOptions::intrinsics_sigma): unknowns under a prior of that σ,
/// whose covariance of the camera's pose is the solve's "consider" covariance
/// A⁻¹ + G Σ_post Gᵀ (see PoseUncertainty::from_given_intrinsics), plus the
/// shift G δc the solve adds for the error δc its views suggest, here at the
/// median of its square over the noise. Where the solve uses its
/// camera-to-camera terms (PlanCell::cross_terms), the information holds them
/// as the solve's covariance does: the points of a view that other cameras
/// share once more per such camera, through a pose block of its own. The
/// poses are chosen by the views' information without them.

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "handeye/core/calibration.h"
#include "handeye/core/camera.h"
#include "handeye/core/dataset.h"
#include "handeye/core/target.h"

namespace handeye {

/// A camera as known before the capture.
struct PlanCamera {
  Camera camera;  ///< name, image size, intrinsics (a guess when `refine_intrinsics`)
  /// Its rough pose: T_base_cam (eye_to_hand) or T_ee_cam (eye_in_hand).
  Eigen::Isometry3d T_mount_cam = Eigen::Isometry3d::Identity();
  /// How far the rough pose may be off (the user's ±): metres, radians. It
  /// widens the visibility margin and weighs in the choice of poses; the
  /// predicted σ gives the rough pose no weight, as the solve gives it none.
  double position_sigma_m = 0.1;
  double rotation_sigma_rad = 10.0 * M_PI / 180.0;
  /// fx, fy, cx, cy will be unknowns of the solve (`--refine-intrinsics
  /// focal,principal_point`, or intrinsics not given): views at varied
  /// depths are then needed to tell focal length from distance.
  bool refine_intrinsics = false;
  /// None are given (with `refine_intrinsics`): the solve estimates k1, k2,
  /// p1, p2 as well, which views towards the image's corners determine.
  bool intrinsics_unknown = false;
  /// Its own detection noise σ per image axis (pixels) where it detects
  /// unlike the others (blur, resolution, distance); 0: the cell's
  /// PlanCell::pixel_sigma_px. `advise` sets it from each solved camera's
  /// residuals.
  double pixel_sigma_px = 0;
  /// `advise`: what the recorded capture's solve found its given fx, fy, cx,
  /// cy off by (CameraResult::given_intrinsics_offset_px). The forecast keeps
  /// the shift that causes as far as it stands out of the views' noise.
  std::optional<Eigen::Vector4d> given_intrinsics_offset_px;
};

/// Where the robot may put the flange.
struct PlanRegion {
  /// Box for the flange position (T_base_ee's translation) in the base
  /// frame, metres; unset: only `taught` poses are candidates.
  std::optional<Eigen::AlignedBox3d> box;
  /// Poses the user taught (T_base_ee); candidates as they are.
  std::vector<Eigen::Isometry3d> taught;
  /// The tool's z axis (T_base_ee's third column) stays within max_tilt_rad
  /// of `tilt_axis` (base frame, unit); max_tilt_rad ≥ π: no limit.
  Eigen::Vector3d tilt_axis = Eigen::Vector3d::UnitZ();
  double max_tilt_rad = M_PI;
};

/// What a camera needs to detect the target in a view.
struct ViewConstraints {
  double margin_px = 20;            ///< the whole target this far inside the image
  double max_view_angle_deg = 60;   ///< from face-on
  double min_square_px = 12;        ///< spacing of neighbouring target points, pixels
};

/// What is known before the capture (the CELL file).
struct PlanCell {
  Setup setup = Setup::kEyeToHand;
  std::shared_ptr<const Target> target;
  std::vector<PlanCamera> cameras;
  /// Rough T_ee_target (eye_to_hand) or T_base_target (eye_in_hand) and its ±.
  Eigen::Isometry3d T_holder_target = Eigen::Isometry3d::Identity();
  double target_position_sigma_m = 0.05;
  double target_rotation_sigma_rad = 10.0 * M_PI / 180.0;
  double pixel_sigma_px = 0.2;       ///< detection noise σ per image axis
  double robot_sigma_mm = 0.3;       ///< robot pose error σ per axis of the flange position
  double robot_sigma_deg = 0.03;     ///< and of its rotation
  /// How well the given intrinsics of the cameras not refined are known
  /// (the solve's --intrinsics-sigma; {0, 0}: exact).
  GivenIntrinsicsSigma intrinsics_sigma;
  /// Whether the solve uses its camera-to-camera terms
  /// (CalibrationOptions::cross_terms): they use the points of a view that
  /// other cameras share once more per camera, and the σ the solve reports
  /// counts them as such, so the predicted σ does too.
  bool cross_terms = true;
  PlanRegion region;
  ViewConstraints constraints;
  bool Check(std::string* why) const;
};

/// Predicted 1σ of one camera's pose (as CameraResult::sigma: sqrt of the
/// trace of the position and rotation covariance).
struct PredictedSigma {
  double position_mm = 0;
  double rotation_deg = 0;
  /// position_mm without what the given intrinsics' uncertainty adds: the
  /// views alone (as PoseUncertainty::OwnPositionMm).
  double own_position_mm = 0;
};

/// One planned pose.
struct PlannedPose {
  std::string id;
  Eigen::Isometry3d T_base_ee = Eigen::Isometry3d::Identity();
  std::vector<std::string> cameras;  ///< which cameras see the whole target
  /// Per camera: the σ predicted once this pose and every earlier one is recorded.
  std::map<std::string, PredictedSigma> sigma_after;
};

/// How to plan.
struct PlanOptions {
  int poses = 12;           ///< how many poses (the most, with goal_mm)
  double goal_mm = 0;       ///< > 0: stop at the fewest poses whose worst σ is within it
  std::uint64_t seed = 1;   ///< candidate sampling
  /// Candidates drawn in the box. On bench/plan's cells (12 seeds) 8000
  /// made the worst camera of 12 planned poses 1.41 / 2.02 / 2.13× as good
  /// as 30 sampled poses (small / medium / large), 3000 1.15 / 1.98 / 1.83×.
  int candidates = 8000;
  int threads = 0;          ///< threads the candidates are weighed on (0 = all cores)
  /// The share of the rough poses' ± (PlanCamera::position_sigma_m,
  /// rotation_sigma_rad, the target's) kept free around the target in the
  /// image, beyond constraints.margin_px: 1 keeps the whole ±, 0 plans on the
  /// rough poses as if exact. Half by default: on rendered small, medium and
  /// large cells whose rough poses were off by ± 100 mm / 10° (bench_plan
  /// --rough-mm 100 --rough-deg 10, 6 seeds each), the whole ± pushed the
  /// target to the image centre and the worst camera of 12 planned poses was
  /// 0.60 / 1.25 / 0.76× as good as with 30 sampled poses; half of it gave
  /// 1.08 / 1.50 / 1.83×, and the true cells showed the whole target in at
  /// least as many views as the plan counted on (197/180, 173/152, 169/144).
  /// With ± 20 mm / 1° the two plan alike. With the exchange and 8000
  /// candidates (2026-12-02): whole 0.87 / 1.60 / 1.47×, half 0.49 / 2.10 /
  /// 1.78× (the small cell's planned views hid the robot's error in 3 of
  /// the 6 solves, which then took the robot as exact).
  double uncertainty_margin = 0.5;
  bool Check(std::string* why) const;
};

/// A plan, or why none reaches what was asked.
struct CapturePlan {
  std::vector<PlannedPose> poses;
  /// Empty when the plan does what was asked; else why not (a region no
  /// camera sees, a goal out of reach): `handeye plan` exits 3 with it.
  std::string failure;
  /// The worst camera's σ after the last pose (the best reachable when the goal is not).
  double worst_position_mm = 0;
  std::string worst_camera;
  int candidates = 0;  ///< candidates that passed the constraints
  /// What holds each camera's σ after the last pose back: its position σ
  /// (mm) from the same views were its intrinsics known exactly (refined or
  /// given alike), and were the robot's poses exact. Where the first is far
  /// below worst_position_mm, the focal length trading against the distance
  /// along the camera's axis is what costs (views at more varied depths, or
  /// nearer the camera, pin it); where the second is, the robot's error.
  std::map<std::string, double> intrinsics_exact_mm, robot_exact_mm;
};

/// Chooses poses greedily by the information they add (see the file comment),
/// then exchanges each for a candidate that adds more beside the others,
/// each in the region, within the tilt limits and seen by at least one camera
/// under the constraints (with the rough poses' ± as extra margin).
/// `recorded`: poses already captured with the cameras that saw the target
/// (advise), counted first and not output.
CapturePlan PlanCapture(const PlanCell& cell, const PlanOptions& options,
                        const std::vector<PlannedPose>& recorded = {});

/// The σ predicted per camera for exactly these poses (their views under the constraints).
std::map<std::string, PredictedSigma> PredictSigma(const PlanCell& cell,
                                                   const std::vector<Eigen::Isometry3d>& poses);

/// The σ predicted per camera for poses already recorded, each with the cameras that saw the target.
std::map<std::string, PredictedSigma> PredictSigmaOfViews(const PlanCell& cell,
                                                          const std::vector<PlannedPose>& recorded);

/// Which cameras see the whole target at T_base_ee under the cell's constraints.
std::vector<std::string> CamerasSeeing(const PlanCell& cell, const Eigen::Isometry3d& T_base_ee);

/// True when T_base_ee lies in the region's box (when it has one; taught poses
/// count as in it) and within its tilt limits.
bool InRegion(const PlanRegion& region, const Eigen::Isometry3d& T_base_ee);

}  // namespace handeye
