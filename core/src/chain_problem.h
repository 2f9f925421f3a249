// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The one place in core that creates the chain's ceres::Problem: the joint
// and per-camera solves, the intrinsics check, the drift check and the
// noise-only bound build theirs here, each saying which blocks are free and
// which held (tests/CMakeLists.txt checks with nm that no other object
// constructs a ceres::Problem).

#include <ceres/problem.h>

#include <Eigen/Geometry>
#include <array>
#include <vector>

#include "handeye/core/camera.h"
#include "handeye/core/dataset.h"
#include "robot_error.h"

namespace handeye::internal {

struct RobotPrior;

/// A chain problem (pose blocks on the pose manifold, intrinsics blocks with
/// their held parameters) over parameter blocks that lie in one buffer, in
/// the order they are added. Where it is given no order, Ceres orders blocks
/// by their address (within a group of the linear solver's ordering, and the
/// covariance's columns); blocks allocated one by one lie wherever the heap
/// puts them, so the same solve rounded differently in another process (the
/// Python module against the CLI). In one buffer, every process orders, and
/// rounds, alike.
class ChainProblem {
 public:
  /// Room for `num_poses` pose blocks and `num_intrinsics` intrinsics blocks:
  /// adding more would move the blocks Ceres holds, and throws.
  ChainProblem(size_t num_poses, size_t num_intrinsics);
  ChainProblem(const ChainProblem&) = delete;
  ChainProblem& operator=(const ChainProblem&) = delete;

  ceres::Problem& problem() { return problem_; }
  const ceres::Problem& problem() const { return problem_; }

  /// A pose block (quaternion x, y, z, w then translation) at T, held at T
  /// when `constant`.
  double* AddPose(const Eigen::Isometry3d& T, bool constant = false);
  /// A camera's 18 intrinsics `K` as a block whose `unknowns` (ascending
  /// OpenCVCameraModel indices) are free, the others held.
  double* AddIntrinsics(const std::array<double, OpenCVCameraModel::kNumParams>& K,
                        const std::vector<int>& unknowns);
  /// A robot pose as a block (T_mount_holder, started at `start`), tied to the
  /// reported `pose` by the robot's prior; `prior` (may be null) receives the
  /// prior's residual block.
  double* AddRobotPose(const Eigen::Isometry3d& start, const RobotPose& pose, Setup setup,
                       const RobotPrior& robot, ceres::ResidualBlockId* prior = nullptr);

  static Eigen::Isometry3d Pose(const double* block);

 private:
  double* Add(const double* values, size_t size);

  ceres::Problem problem_;
  std::vector<double> storage_;
};

}  // namespace handeye::internal
