// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Internal pieces of capture planning (handeye/core/plan.h): the unknowns'
// layout, the information a robot pose adds, the candidates and their views.

#include <Eigen/Core>
#include <map>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "handeye/core/plan.h"
#include "handeye/core/transform.h"

namespace handeye::plan_internal {

/// The cell in the solver's terms at the rough values: the unknowns' tangent
/// coordinates in one vector (T_holder_target, then per camera its
/// T_cam_mount and, when refined, fx fy cx cy; when given, the error of the
/// given values: the focal length's relative error, one for fx and fy, and
/// cx, cy, each where PlanCell::intrinsics_sigma makes it uncertain).
struct Model {
  const PlanCell* cell = nullptr;
  int size = 0;                        ///< length of the unknowns' vector
  int target_offset = 0;               ///< T_holder_target's 6 tangent coordinates
  std::vector<int> camera_offset;      ///< T_cam_mount's 6, per camera
  std::vector<int> intrinsics_offset;  ///< its intrinsics_count, per camera; -1: fixed
  std::vector<int> intrinsics_count;   ///< 4 (fx fy cx cy) or 8 (and k1 k2 p1 p2), per camera
  /// Per camera: its given intrinsics' error coordinates; -1: refined, or exact.
  std::vector<int> given_offset;
  bool given_focal = false;            ///< the focal length's error is a coordinate
  bool given_principal_point = false;  ///< cx's and cy's are
  /// How many coordinates each given camera's error takes.
  int GivenCoordinates() const { return (given_focal ? 1 : 0) + (given_principal_point ? 2 : 0); }
  std::vector<PoseParams> T_cam_mount;
  /// Per camera: d(position of T_mount_cam, mm)/d(tangent of T_cam_mount)
  /// (internal::UncertaintyJacobian's first rows), for OwnPositionMm.
  std::vector<Eigen::Matrix<double, 3, 6>> position_jacobian;
  /// The solve's camera-to-camera terms (CalibrationOptions::cross_terms):
  /// per ordered pair (k, t) the offset of T_camk_mount as seen through
  /// camera t, a pose block of its own (refine_joint.cc); empty without them.
  std::map<std::pair<int, int>, int> pair_offset;
  PoseParams T_holder_target{};
  /// Information of what is known before any view (the rough poses' ±, the
  /// intrinsics' prior): keeps cameras without views finite.
  Eigen::MatrixXd prior;
  /// With HoldRecorded: the recorded views' information on the given
  /// intrinsics' error coordinates, as much as each camera's offset is kept
  /// (S, in the order the coordinates take in the unknowns), and the offset
  /// kept (δc, the same order; PlanCamera::given_intrinsics_offset_px).
  /// Empty: no camera has one, every view's noise is a draw.
  Eigen::MatrixXd recorded_information_on_given;
  Eigen::VectorXd recorded_given_offset;
  /// Smallest distance between two target points, metres.
  double point_spacing_m = 0;
  /// Per camera: extra image margin (px) for its rough pose's and the target's ±.
  std::vector<double> uncertainty_margin_px;
};

/// What a model is for. kChoice: the information poses are chosen by, each
/// view's points once and the rough poses' ± as a prior (the choice was tuned
/// so: bench/plan). kForecast: the σ the solve will report, which has no prior
/// on the poses, and uses its camera-to-camera terms where
/// PlanCell::cross_terms says so.
enum class ModelUse { kChoice, kForecast };

Model MakeModel(const PlanCell& cell, ModelUse use = ModelUse::kChoice);

/// The information (inverse covariance, in the units of the unknowns'
/// tangent) that the views of `cameras` at robot pose T_base_ee add, with the
/// pose's own robot error marginalised out; with the model's pair terms, each
/// view's points once more through every other camera of `cameras`, as the
/// solve's camera-to-camera terms use them.
Eigen::MatrixXd PoseInformation(const Model& model, const Eigen::Isometry3d& T_base_ee,
                                const std::vector<int>& cameras);

/// For `advise`: `information` (prior included) is the recorded views', and
/// the cameras' PlanCamera::given_intrinsics_offset_px what their solve
/// found; SigmaOf then keeps as much of that shift as stands out of the
/// recorded views' noise, and draws the rest of the noise afresh. Nothing
/// changes where no camera has an offset.
void HoldRecorded(const Eigen::MatrixXd& information, Model* model);

/// Per camera, its σ under the total information `information` (prior
/// included); infinite when the information is singular.
///
/// The σ the solve reports where the given intrinsics are right. It holds
/// them (c) and reports for its estimate x the covariance A⁻¹ (A the
/// views' information on x) plus G (δc δcᵀ + Σ_post) Gᵀ: G = A⁻¹ A_xc moves
/// x with c's error, Σ_post is what is left of c's prior after the views, δc
/// the error the views' own noise suggests (ConsiderCovariance). With c's
/// errors unknowns under their prior, the inverse H⁻¹ of the information
/// gives H⁻¹_xx = A⁻¹ + G Σ_post Gᵀ; over the noise E[δc δcᵀ] = Σ_post S Σ_post
/// (S the views' information on c), i.e. H⁻¹_xc S H⁻¹_cx, S = (H⁻¹_cc)⁻¹ − P.
/// (Without that term the medium cells of bench/plan predicted 0.69 of the σ
/// reported (median); with c's error under the whole prior, A⁻¹ + G Σ_prior
/// Gᵀ, 1.5-6 times, and the plans made for it were worse.)
/// The shift G δc is one draw of the noise, its square skewed like a χ² of
/// few degrees of freedom: the σ forecast is the median of the σ reported,
/// with the shift's square at its median (MedianSquaredNorm), not its mean
/// (bench/plan, 4-6 cameras, 6 seeds: forecast over reported, median 1.37 /
/// 1.50 / 1.67 on small / medium / large cells with the mean, 1.24 / 1.32 /
/// 1.45 with the median; 1.09 / 1.24 / 1.22 once the rough poses add no
/// information, and 0.83 / 1.06 / 1.06 once it holds the solve's
/// camera-to-camera terms as well, Model::pair_offset. What is left is
/// mostly single draws: the shift the views suggest 10-30 times the views'
/// own σ in a few solves, and views the simulator gives that the plan does
/// not count on).
/// own_position_mm has no shift: the σ of the views alone.
std::vector<PredictedSigma> SigmaOf(const Model& model, const Eigen::MatrixXd& information);

/// Per camera, SigmaOf's own_position_mm alone (the σ of the views with the
/// given intrinsics held), for the choice of poses: the inverse of the
/// information without the given intrinsics' coordinates, several times
/// cheaper than SigmaOf. Infinite where that information is singular.
std::vector<double> OwnPositionMm(const Model& model, const Eigen::MatrixXd& information);

/// Cameras that see the whole target at T_base_ee under the constraints, the
/// margin widened by the rough poses' ±.
std::vector<int> VisibleCameras(const Model& model, const Eigen::Isometry3d& T_base_ee);

/// Candidate poses: the taught ones and `count` drawn in the box, each
/// turned towards one camera or between two, within the tilt limits.
std::vector<Eigen::Isometry3d> DrawCandidates(const Model& model, int count, std::mt19937_64* rng);

}  // namespace handeye::plan_internal
