// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The intrinsics in the engine: which are free, their priors and σ, the
// estimate from the views alone and the check of the given ones (intrinsics.cc).

#include <array>
#include <map>
#include <optional>
#include <vector>

#include "problem.h"
#include "robot_error.h"

namespace ceres {
class CostFunction;
}  // namespace ceres

namespace handeye::internal {

/// The intrinsics (OpenCVCameraModel indices) of `camera` that the groups
/// (IntrinsicsGroup flags) make unknowns: distortion is k1, k2, p1, p2 and
/// every further non-zero coefficient, never the tilt.
std::vector<int> FreeIntrinsics(const Camera& camera, unsigned groups);

/// 1σ of the prior of each intrinsic parameter about its given value: the
/// value that moves an image corner by 20 px.
std::array<double, OpenCVCameraModel::kNumParams> IntrinsicsPriorSigma(const Camera& camera);

/// The prior residuals of the free intrinsics about `given`, in the units of
/// pixel residuals of σ `pixel_sigma_px`. Block: the camera's 18 intrinsics.
ceres::CostFunction* IntrinsicsPrior(const Camera& given, const std::vector<int>& free,
                                     double pixel_sigma_px);

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
ceres::CostFunction* UncertainIntrinsicsPrior(const Camera& camera,
                                              const UncertainIntrinsics& uncertain,
                                              double pixel_sigma_px);
/// The information that prior gives `uncertain.params` (diagonal, its units).
Eigen::MatrixXd UncertainIntrinsicsPriorInformation(const UncertainIntrinsics& uncertain,
                                                    double pixel_sigma_px);
/// `free` and `uncertain.params` together, ascending: a block's tangent
/// coordinates; *uncertain_tangent gets where the uncertain ones are in it.
std::vector<int> IntrinsicsUnknowns(const std::vector<int>& free,
                                    const UncertainIntrinsics& uncertain,
                                    std::vector<int>* uncertain_tangent);

/// The free intrinsics the views hardly determine: their 1σ after the solve
/// is more than half their prior's (the prior, not the views, holds them).
std::vector<int> UndeterminedIntrinsics(
    const Camera& given, const std::array<double, OpenCVCameraModel::kNumParams>& sigma,
    const std::vector<int>& free);

/// Intrinsics of camera `k` estimated from its views alone (closed form from
/// the views' homographies, then OpenCV's calibration: fx, fy, cx, cy, k1,
/// k2, p1, p2), for a camera whose dataset gives none. Throws SolveError with
/// advice when the views are too few or too alike even for a start.
struct EstimatedIntrinsics {
  Camera camera;
  /// Empty where the views alone determine fx, fy, cx, cy (1σ within 5 % of
  /// the focal length and the image side); else what they give, with 1σ: a
  /// start only, which the joint solve with the robot's motions must make good.
  std::string weakly;
};
EstimatedIntrinsics EstimateIntrinsics(const Dataset& dataset, int k);

/// The check of the given intrinsics after a solve: per camera, fx, fy, cx,
/// cy as the camera's views alone say (its T_cam_mount, its own T_holder_target and
/// those four free); a
/// warning where a group in `check[k]` (kFocal, kPrincipalPoint) differs from
/// the given values by more than 3σ and by a visible amount (0.3 % of the
/// focal length, 0.5 px).
/// With `robot`, each robot pose is a block under that prior, as in the joint solve.
/// With `found`: per camera warned about, what the check found (IntrinsicsOff).
struct IntrinsicsOff {
  /// How far the given values of the groups the warning names move
  /// T_cam_mount from where the views' own intrinsics put it (tangent of
  /// T_cam_mount, linearised: C_xK C_KK⁻¹ ΔK from the same covariance); a
  /// bias the covariance of the joint solve does not hold.
  Eigen::Matrix<double, 6, 1> moved;
  /// ΔK of those groups: the views' fx, fy, cx, cy less the given (0 for a group not named).
  Eigen::Vector4d offset_px;
  /// The groups the warning names (kFocal, kPrincipalPoint).
  unsigned Groups() const {
    return (offset_px[0] != 0 || offset_px[1] != 0 ? kFocal : 0u) |
           (offset_px[2] != 0 || offset_px[3] != 0 ? kPrincipalPoint : 0u);
  }
};
std::vector<Warning> IntrinsicsWarnings(
    const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target, double cauchy_scale_px, const std::vector<unsigned>& check,
    const std::optional<RobotPrior>& robot, std::map<size_t, IntrinsicsOff>* found = nullptr);

}  // namespace handeye::internal
