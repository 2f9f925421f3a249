// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/uncertainty.h"

#include <ceres/covariance.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/product_manifold.h>

#include <memory>

#include "handeye/core/cost_functions.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"

namespace handeye {
namespace {

// Jacobians, with respect to a pose block's tangent (Ceres' quaternion
// manifold turns by 2|δ| for a step δ, hence differentiate rather than assume),
// of the camera position c = −R_Xᵀ t_X and of the orientation change (rotation
// vector of R_X(δ) · R_Xᵀ, whose angle is that of the camera's own orientation change).
struct TangentJacobians {
  Eigen::Matrix<double, 3, 6> position;
  Eigen::Matrix<double, 3, 6> rotation;
};

TangentJacobians PoseJacobians(const PoseParams& X) {
  ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>> manifold;
  const Eigen::Isometry3d X0 = FromPoseParams(X.data());
  TangentJacobians J;
  const double h = 1e-7;
  for (int i = 0; i < 6; ++i) {
    Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
    PoseParams plus = X, minus = X;
    d(i) = h;
    manifold.Plus(X.data(), d.data(), plus.data());
    d(i) = -h;
    manifold.Plus(X.data(), d.data(), minus.data());
    const Eigen::Isometry3d Xp = FromPoseParams(plus.data()), Xm = FromPoseParams(minus.data());
    J.position.col(i) = (Eigen::Vector3d(Xp.inverse().translation()) -
                         Eigen::Vector3d(Xm.inverse().translation())) / (2 * h);
    J.rotation.col(i) = (RotationVectorFromMatrix(Xp.linear() * X0.linear().transpose()) -
                         RotationVectorFromMatrix(Xm.linear() * X0.linear().transpose())) / (2 * h);
  }
  return J;
}

}  // namespace

PositionCovariance ComputePositionCovariance(const Dataset& dataset, const CalibrationResult& at,
                                             double noise_px) {
  using PoseManifold = ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>;
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  PoseParams Z = ToPoseParams(at.T_target);
  problem.AddParameterBlock(Z.data(), 7, new PoseManifold());
  std::vector<PoseParams> X(dataset.cameras.size());
  std::vector<bool> has_views(dataset.cameras.size(), false);
  for (size_t k = 0; k < X.size(); ++k) {
    if (k >= at.cameras.size() || !at.cameras[k].calibrated) continue;
    X[k] = ToPoseParams(at.cameras[k].T_cam.inverse());
  }
  for (const auto& obs : dataset.observations) {
    const int k = dataset.CameraIndex(obs.camera);
    const int j = dataset.PoseIndex(obs.pose_id);
    if (k < 0 || j < 0 || !at.cameras[k].calibrated) continue;
    if (!has_views[k]) {
      problem.AddParameterBlock(X[k].data(), 7, new PoseManifold());
      has_views[k] = true;
    }
    const Eigen::Isometry3d M = dataset.setup == Setup::kEyeToHand ? dataset.poses[j].T_base_ee
                                                                   : dataset.poses[j].T_base_ee.inverse();
    ViewPoints points;
    for (size_t i = 0; i < obs.ids.size(); ++i) {
      const TargetPoint* p = dataset.target->FindPoint(obs.ids[i]);
      if (!p) continue;
      points.p_target.push_back(p->p_target);
      points.observed_px.push_back(obs.points_px[i]);
    }
    if (points.p_target.empty()) continue;
    // No robust loss: the bound is for Gaussian noise on every point.
    problem.AddResidualBlock(ViewReprojectionError::Create(dataset.cameras[k], M, std::move(points), 0.0),
                             nullptr, X[k].data(), Z.data());
  }
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(options);
  std::vector<std::pair<const double*, const double*>> blocks;
  for (size_t k = 0; k < X.size(); ++k)
    if (has_views[k]) blocks.emplace_back(X[k].data(), X[k].data());
  if (!covariance.Compute(blocks, &problem))
    throw SolveError("the calibration is not observable from these views (singular information matrix)");
  PositionCovariance out;
  for (size_t k = 0; k < X.size(); ++k) {
    if (!has_views[k]) continue;
    Eigen::Matrix<double, 6, 6, Eigen::RowMajor> C;
    covariance.GetCovarianceBlockInTangentSpace(X[k].data(), X[k].data(), C.data());
    C *= noise_px * noise_px;
    const TangentJacobians J = PoseJacobians(X[k]);
    out.camera_position[dataset.cameras[k].name] = J.position * C * J.position.transpose();
    out.camera_rotation[dataset.cameras[k].name] = J.rotation * C * J.rotation.transpose();
  }
  return out;
}

}  // namespace handeye
