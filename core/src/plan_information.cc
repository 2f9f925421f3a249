// SPDX-License-Identifier: GPL-2.0-or-later
// What a robot pose tells the solve (handeye/core/plan.h): the Fisher
// information of its views through the solver's own cost functions, with the
// pose's robot error marginalised out, and the σ per camera it leads to.
#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <memory>

#include "cost_functions.h"
#include "handeye/core/setup_frames.h"
#include "intrinsics_internal.h"
#include "plan_internal.h"
#include "problem.h"

namespace handeye::plan_internal {
namespace {

constexpr int kIntrinsicsUnknowns = 4;  // fx fy cx cy
using Tangent = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;
using DynamicRowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// d(block)/d(tangent) of a pose block at `params` (PoseManifold).
Tangent PlusJacobian(const PoseParams& params) {
  internal::PoseManifold manifold;
  Tangent J;
  manifold.PlusJacobian(params.data(), J.data());
  return J;
}

double SmallestSpacing(const Target& target) {
  double best = std::numeric_limits<double>::infinity();
  const auto& points = target.Points();
  for (size_t i = 0; i < points.size(); ++i)
    for (size_t j = i + 1; j < points.size(); ++j)
      best = std::min(best, (points[i].p_target - points[j].p_target).norm());
  return std::isfinite(best) ? best : 0.0;
}

/// Information of the rough knowledge: each camera's and the target's ±
/// (weak, so that unseen cameras stay finite) and the intrinsics' prior the solve uses.
void AddPrior(const PlanCell& cell, Model* model) {
  model->prior = Eigen::MatrixXd::Zero(model->size, model->size);
  // The quaternion tangent turns by twice its length.
  auto add_pose = [&](int offset, const Eigen::Isometry3d& T_mount_cam, double sigma_m,
                      double sigma_rad) {
    const double lever = T_mount_cam.translation().norm() * sigma_rad;
    const double sigma_t = std::sqrt(sigma_m * sigma_m + lever * lever);
    for (int i = 0; i < 3; ++i) {
      model->prior(offset + i, offset + i) = 4.0 / (sigma_rad * sigma_rad);
      model->prior(offset + 3 + i, offset + 3 + i) = 1.0 / (sigma_t * sigma_t);
    }
  };
  add_pose(model->target_offset, cell.T_holder_target, cell.target_position_sigma_m,
           cell.target_rotation_sigma_rad);
  for (size_t k = 0; k < cell.cameras.size(); ++k) {
    const PlanCamera& camera = cell.cameras[k];
    add_pose(model->camera_offset[k], camera.T_mount_cam, camera.position_sigma_m,
             camera.rotation_sigma_rad);
    if (model->intrinsics_offset[k] < 0) continue;
    const auto sigma = internal::IntrinsicsPriorSigma(camera.camera);
    for (int i = 0; i < kIntrinsicsUnknowns; ++i)
      model->prior(model->intrinsics_offset[k] + i, model->intrinsics_offset[k] + i) =
          1.0 / (sigma[i] * sigma[i]);
  }
}

}  // namespace

Model MakeModel(const PlanCell& cell) {
  Model model;
  model.cell = &cell;
  model.target_offset = 0;
  model.size = 6;
  for (const PlanCamera& camera : cell.cameras) {
    model.camera_offset.push_back(model.size);
    model.size += 6;
    model.intrinsics_offset.push_back(camera.refine_intrinsics ? model.size : -1);
    if (camera.refine_intrinsics) model.size += kIntrinsicsUnknowns;
    model.T_cam_mount.push_back(ToPoseParams(camera.T_mount_cam.inverse()));
    // Where the rough pose's ± may move the image: its position over the
    // working distance and its turn, each in pixels at the focal length.
    const double f = std::max(camera.camera.fx(), camera.camera.fy());
    const double distance = std::max(0.3, camera.T_mount_cam.translation().norm());
    const double position = camera.position_sigma_m + cell.target_position_sigma_m;
    model.uncertainty_margin_px.push_back(
        f * (position / distance + std::tan(camera.rotation_sigma_rad)));
  }
  model.T_holder_target = ToPoseParams(cell.T_holder_target);
  model.point_spacing_m = SmallestSpacing(*cell.target);
  AddPrior(cell, &model);
  return model;
}

Eigen::MatrixXd PoseInformation(const Model& model, const Eigen::Isometry3d& T_base_ee,
                                const std::vector<int>& cameras) {
  const PlanCell& cell = *model.cell;
  const SetupFrames frames = FramesOf(cell.setup);
  const PoseParams T_mount_holder = ToPoseParams(frames.MountFromHolder(T_base_ee));
  const bool robot_error = cell.robot_sigma_mm > 0 && cell.robot_sigma_deg > 0;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(model.size, model.size);       // unknowns
  Eigen::MatrixXd H_ur = Eigen::MatrixXd::Zero(model.size, 6);             // unknowns × robot
  Eigen::Matrix<double, 6, 6> H_rr = Eigen::Matrix<double, 6, 6>::Zero();  // robot
  const Tangent P_robot = PlusJacobian(T_mount_holder),
                P_target = PlusJacobian(model.T_holder_target);
  for (int k : cameras) {
    const Camera& camera = cell.cameras[k].camera;
    auto points = std::make_shared<ViewPoints>();
    const Eigen::Isometry3d T_cam_target = FromPoseParams(model.T_cam_mount[k].data()) *
                                           FromPoseParams(T_mount_holder.data()) *
                                           cell.T_holder_target;
    for (const TargetPoint& p : cell.target->Points()) {
      const auto uv = camera.Project(T_cam_target * p.p_target);
      if (!uv) continue;
      points->p_target.push_back(p.p_target);
      points->observed_px.push_back(*uv);
    }
    if (points->p_target.empty()) continue;
    const bool free = model.intrinsics_offset[k] >= 0;
    std::unique_ptr<ceres::CostFunction> cost(
        ViewReprojectionWithRobotError::Create(camera, points, 0.0, free));
    const int rows = cost->num_residuals();
    std::vector<DynamicRowMajor> J(free ? 4 : 3);
    for (size_t b = 0; b < J.size(); ++b) J[b].resize(rows, cost->parameter_block_sizes()[b]);
    const double* parameters[4] = {model.T_cam_mount[k].data(), T_mount_holder.data(),
                                   model.T_holder_target.data(), camera.params.data()};
    double* jacobians[4] = {J[0].data(), J[1].data(), J[2].data(), free ? J[3].data() : nullptr};
    Eigen::VectorXd residuals(rows);
    if (!cost->Evaluate(parameters, residuals.data(), jacobians)) continue;
    // d(residuals)/d(unknowns' tangent) and d/d(robot tangent).
    Eigen::MatrixXd J_u = Eigen::MatrixXd::Zero(rows, model.size);
    J_u.middleCols(model.camera_offset[k], 6) = J[0] * PlusJacobian(model.T_cam_mount[k]);
    J_u.middleCols(model.target_offset, 6) = J[2] * P_target;
    if (free)
      J_u.middleCols(model.intrinsics_offset[k], kIntrinsicsUnknowns) =
          J[3].leftCols(kIntrinsicsUnknowns);
    const Eigen::MatrixXd J_r = J[1] * P_robot;
    H += J_u.transpose() * J_u;
    if (!robot_error) continue;
    H_ur += J_u.transpose() * J_r;
    H_rr += J_r.transpose() * J_r;
  }
  if (robot_error) {
    // The prior on the pose block as the solve weighs it, in pixel units.
    std::unique_ptr<ceres::CostFunction> prior(RobotPosePrior::Create(
        T_base_ee, frames.RobotPoseInverted(), cell.robot_sigma_deg * M_PI / 180.0,
        cell.robot_sigma_mm / 1000.0, cell.pixel_sigma_px));
    Eigen::Matrix<double, 6, 7, Eigen::RowMajor> J_prior;
    Eigen::Matrix<double, 6, 1> r;
    const double* parameters[1] = {T_mount_holder.data()};
    double* jacobians[1] = {J_prior.data()};
    prior->Evaluate(parameters, r.data(), jacobians);
    const Eigen::Matrix<double, 6, 6> J_p = J_prior * P_robot;
    H_rr += J_p.transpose() * J_p;
    H -= H_ur * H_rr.ldlt().solve(H_ur.transpose());
  }
  return H / (cell.pixel_sigma_px * cell.pixel_sigma_px);
}

std::vector<PredictedSigma> SigmaOf(const Model& model, const Eigen::MatrixXd& information) {
  const size_t cameras = model.camera_offset.size();
  std::vector<PredictedSigma> out(
      cameras, {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()});
  const Eigen::LLT<Eigen::MatrixXd> llt(information);
  if (llt.info() != Eigen::Success) return out;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(model.size, 6 * cameras);
  for (size_t k = 0; k < cameras; ++k) rhs.block(model.camera_offset[k], 6 * k, 6, 6).setIdentity();
  const Eigen::MatrixXd columns = llt.solve(rhs);
  for (size_t k = 0; k < cameras; ++k) {
    const Eigen::Matrix<double, 6, 6> C = columns.block(model.camera_offset[k], 6 * k, 6, 6);
    const PoseUncertainty u = internal::UncertaintyOf(FromPoseParams(model.T_cam_mount[k].data()),
                                                      0.5 * (C + C.transpose()), true);
    out[k] = {u.position_mm, u.rotation_deg};
  }
  return out;
}

}  // namespace handeye::plan_internal
