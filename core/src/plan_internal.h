// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Internal pieces of capture planning (handeye/core/plan.h): the unknowns'
// layout, the information a robot pose adds, the candidates and their views.

#include <Eigen/Core>
#include <optional>
#include <random>
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
  std::vector<int> intrinsics_offset;  ///< fx fy cx cy, per camera; -1: fixed
  /// Per camera: its given intrinsics' error coordinates; -1: refined, or exact.
  std::vector<int> given_offset;
  bool given_focal = false;            ///< the focal length's error is a coordinate
  bool given_principal_point = false;  ///< cx's and cy's are
  /// How many coordinates each given camera's error takes.
  int GivenCoordinates() const { return (given_focal ? 1 : 0) + (given_principal_point ? 2 : 0); }
  std::vector<PoseParams> T_cam_mount;
  PoseParams T_holder_target{};
  /// Information of what is known before any view (the rough poses' ±, the
  /// intrinsics' prior): keeps cameras without views finite.
  Eigen::MatrixXd prior;
  /// Smallest distance between two target points, metres.
  double point_spacing_m = 0;
  /// Per camera: extra image margin (px) for its rough pose's and the target's ±.
  std::vector<double> uncertainty_margin_px;
};

Model MakeModel(const PlanCell& cell);

/// The information (inverse covariance, in the units of the unknowns'
/// tangent) that the views of `cameras` at robot pose T_base_ee add, with the
/// pose's own robot error marginalised out.
Eigen::MatrixXd PoseInformation(const Model& model, const Eigen::Isometry3d& T_base_ee,
                                const std::vector<int>& cameras);

/// Per camera, its σ under the total information `information` (prior
/// included); infinite when the information is singular.
std::vector<PredictedSigma> SigmaOf(const Model& model, const Eigen::MatrixXd& information);

/// Cameras that see the whole target at T_base_ee under the constraints, the
/// margin widened by the rough poses' ±.
std::vector<int> VisibleCameras(const Model& model, const Eigen::Isometry3d& T_base_ee);

/// Candidate poses: the taught ones and `count` drawn in the box, each
/// turned towards one camera or between two, within the tilt limits.
std::vector<Eigen::Isometry3d> DrawCandidates(const Model& model, int count, std::mt19937_64* rng);

}  // namespace handeye::plan_internal
