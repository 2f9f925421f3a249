// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/uncertainty.h"

#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/product_manifold.h>

#include <memory>

#include "chain_problem.h"
#include "cost_functions.h"
#include "covariance.h"
#include "handeye/core/error.h"
#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"
#include "pose_manifold.h"
#include "pose_uncertainty.h"

namespace handeye {
namespace internal {

// Ceres' quaternion manifold turns by 2|δ| for a step δ, hence the
// Jacobians with respect to the tangent are differentiated, not assumed.
Eigen::Matrix<double, 6, 6> UncertaintyJacobian(const Eigen::Isometry3d& T, bool invert) {
  PoseManifold manifold;
  const PoseParams T0 = ToPoseParams(T);
  const Eigen::Isometry3d P0 = invert ? T.inverse() : T;
  // d(position mm, rotation deg of P)/d(tangent of T), central differences.
  Eigen::Matrix<double, 6, 6> J;
  const double h = 1e-7;
  for (int i = 0; i < 6; ++i) {
    Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
    PoseParams plus = T0, minus = T0;
    d(i) = h;
    manifold.Plus(T0.data(), d.data(), plus.data());
    d(i) = -h;
    manifold.Plus(T0.data(), d.data(), minus.data());
    Eigen::Isometry3d Pp = FromPoseParams(plus.data()), Pm = FromPoseParams(minus.data());
    if (invert) {
      Pp = Pp.inverse();
      Pm = Pm.inverse();
    }
    J.block<3, 1>(0, i) = 1000.0 * (Pp.translation() - Pm.translation()) / (2 * h);
    J.block<3, 1>(3, i) = (180.0 / M_PI) *
                          (RotationVectorFromMatrix(Pp.linear() * P0.linear().transpose()) -
                           RotationVectorFromMatrix(Pm.linear() * P0.linear().transpose())) /
                          (2 * h);
  }
  return J;
}

PoseUncertainty UncertaintyOf(const Eigen::Isometry3d& T,
                              const Eigen::Matrix<double, 6, 6>& tangent_covariance, bool invert) {
  const Eigen::Matrix<double, 6, 6> J = UncertaintyJacobian(T, invert);
  PoseUncertainty out;
  out.covariance = J * tangent_covariance * J.transpose();
  out.position_mm = std::sqrt(std::max(0.0, out.covariance.topLeftCorner<3, 3>().trace()));
  out.rotation_deg = std::sqrt(std::max(0.0, out.covariance.bottomRightCorner<3, 3>().trace()));
  return out;
}

}  // namespace internal

PositionCovariance ComputePositionCovariance(const Dataset& dataset, const CalibrationResult& at,
                                             double noise_px) {
  internal::ChainProblem chain(1 + dataset.cameras.size(), 0);
  ceres::Problem& problem = chain.problem();
  double* T_holder_target = chain.AddPose(at.T_target);
  std::vector<double*> T_cam_mount(dataset.cameras.size(), nullptr);
  // Every detected point of every observation, at the given values: the bound
  // is for the data as detected, so this does not go through BuildProblem,
  // whose PnP drops views (fewer than 4 points, no plane pose, the target
  // seen from behind) and which the diagnostics measure a solution on.
  for (const auto& obs : dataset.observations) {
    const int k = dataset.CameraIndex(obs.camera);
    const int j = dataset.PoseIndex(obs.pose_id);
    if (k < 0 || j < 0 || !at.cameras[k].calibrated) continue;
    if (!T_cam_mount[k]) T_cam_mount[k] = chain.AddPose(at.cameras[k].T_cam.inverse());
    const Eigen::Isometry3d T_mount_holder =
        FramesOf(dataset.setup).MountFromHolder(dataset.poses[j].T_base_ee);
    ViewPoints points;
    for (size_t i = 0; i < obs.ids.size(); ++i) {
      const TargetPoint* p = dataset.target->FindPoint(obs.ids[i]);
      if (!p) continue;
      points.p_target.push_back(p->p_target);
      points.observed_px.push_back(obs.points_px[i]);
    }
    if (points.p_target.empty()) continue;
    // No robust loss: the bound is for Gaussian noise on every point.
    problem.AddResidualBlock(
        ViewReprojectionError::Create(dataset.cameras[k], T_mount_holder, std::move(points), 0.0),
        nullptr, T_cam_mount[k], T_holder_target);
  }
  internal::BlockCovariance::Pairs blocks;
  for (size_t k = 0; k < T_cam_mount.size(); ++k)
    if (T_cam_mount[k]) blocks.emplace_back(T_cam_mount[k], T_cam_mount[k]);
  const internal::BlockCovariance covariance(&problem, blocks, ceres::DENSE_SVD);
  if (!covariance.ok())
    throw SolveError(
        "the calibration is not observable from these views (singular information matrix)");
  PositionCovariance out;
  for (size_t k = 0; k < T_cam_mount.size(); ++k) {
    if (!T_cam_mount[k]) continue;
    const Eigen::Matrix<double, 6, 6> C = covariance.Tangent(T_cam_mount[k], T_cam_mount[k]);
    const PoseUncertainty u = internal::UncertaintyOf(internal::ChainProblem::Pose(T_cam_mount[k]),
                                                      C * noise_px * noise_px, true);
    constexpr double kMmToM = 1e-3, kDegToRad = M_PI / 180.0;
    out.camera_position[dataset.cameras[k].name] =
        u.covariance.topLeftCorner<3, 3>() * kMmToM * kMmToM;
    out.camera_rotation[dataset.cameras[k].name] =
        u.covariance.bottomRightCorner<3, 3>() * kDegToRad * kDegToRad;
  }
  return out;
}

double PoseUncertainty::OwnPositionMm() const {
  return std::sqrt(
      std::max(0.0, (covariance - from_given_intrinsics).topLeftCorner<3, 3>().trace()));
}

double PoseUncertainty::OwnRotationDeg() const {
  return std::sqrt(
      std::max(0.0, (covariance - from_given_intrinsics).bottomRightCorner<3, 3>().trace()));
}

}  // namespace handeye
