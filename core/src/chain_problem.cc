// SPDX-License-Identifier: GPL-2.0-or-later
// The chain's ceres::Problem and its parameter blocks (chain_problem.h).
#include "chain_problem.h"

#include <ceres/manifold.h>

#include <algorithm>
#include <stdexcept>
#include <tuple>

#include "cost_functions.h"
#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"
#include "pose_manifold.h"
#include "robot_error.h"

namespace handeye::internal {
namespace {

constexpr size_t kPoseParams = std::tuple_size<PoseParams>::value;

ceres::Problem::Options ProblemOptions() {
  ceres::Problem::Options options;
  options.manifold_ownership = ceres::TAKE_OWNERSHIP;
  return options;
}

}  // namespace

ChainProblem::ChainProblem(size_t num_poses, size_t num_intrinsics) : problem_(ProblemOptions()) {
  storage_.reserve(kPoseParams * num_poses + OpenCVCameraModel::kNumParams * num_intrinsics);
}

double* ChainProblem::Add(const double* values, size_t size) {
  if (storage_.size() + size > storage_.capacity())
    throw std::logic_error("ChainProblem: more blocks than the room reserved for them");
  double* block = storage_.data() + storage_.size();
  storage_.insert(storage_.end(), values, values + size);
  return block;
}

double* ChainProblem::AddPose(const Eigen::Isometry3d& T, bool constant) {
  const PoseParams params = ToPoseParams(T);
  double* block = Add(params.data(), params.size());
  problem_.AddParameterBlock(block, kPoseParams, new PoseManifold());
  if (constant) problem_.SetParameterBlockConstant(block);
  return block;
}

double* ChainProblem::AddIntrinsics(const std::array<double, OpenCVCameraModel::kNumParams>& K,
                                    const std::vector<int>& unknowns) {
  constexpr int kN = OpenCVCameraModel::kNumParams;
  double* block = Add(K.data(), K.size());
  problem_.AddParameterBlock(block, kN);
  std::vector<int> constant;
  for (int p = 0; p < kN; ++p)
    if (!std::binary_search(unknowns.begin(), unknowns.end(), p)) constant.push_back(p);
  if (!constant.empty()) problem_.SetManifold(block, new ceres::SubsetManifold(kN, constant));
  return block;
}

double* ChainProblem::AddRobotPose(const Eigen::Isometry3d& start, const RobotPose& pose,
                                   Setup setup, const RobotPrior& robot,
                                   ceres::ResidualBlockId* prior) {
  double* block = AddPose(start);
  const ceres::ResidualBlockId id = problem_.AddResidualBlock(
      RobotPosePrior::Create(pose.T_base_ee, FramesOf(setup).RobotPoseInverted(), robot.sigma_rad,
                             robot.sigma_m, robot.pixel_sigma_px),
      nullptr, block);
  if (prior) *prior = id;
  return block;
}

Eigen::Isometry3d ChainProblem::Pose(const double* block) { return FromPoseParams(block); }

}  // namespace handeye::internal
