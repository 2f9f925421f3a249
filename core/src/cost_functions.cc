// SPDX-License-Identifier: GPL-2.0-or-later
// The cost functions the solver uses: the view costs with hand-chained
// derivatives (cost_jacobians.h) and the robot pose prior.
#include "cost_functions.h"

#include <memory>
#include <utility>

#include "cost_jacobians.h"

namespace handeye {

using cost_internal::ChainedViewCost;
using cost_internal::CrossChainJacobian;
using cost_internal::DirectChainJacobian;
using cost_internal::RobotChainJacobian;

ceres::CostFunction* ViewReprojectionWithRobotError::Create(const Camera& camera,
                                                            std::shared_ptr<const ViewPoints> points,
                                                            double cauchy_scale_px, bool free_intrinsics) {
  return new ChainedViewCost<3, RobotChainJacobian>(camera, std::move(points), cauchy_scale_px, {}, free_intrinsics);
}

ceres::CostFunction* ViewReprojectionError::Create(const Camera& camera, const Eigen::Isometry3d& T_mount_holder,
                                                   ViewPoints points, double cauchy_scale_px) {
  return Create(camera, T_mount_holder, std::make_shared<const ViewPoints>(std::move(points)), cauchy_scale_px);
}

ceres::CostFunction* ViewReprojectionError::Create(const Camera& camera, const Eigen::Isometry3d& T_mount_holder,
                                                   std::shared_ptr<const ViewPoints> points, double cauchy_scale_px,
                                                   bool free_intrinsics) {
  return new ChainedViewCost<2, DirectChainJacobian>(
      camera, std::move(points), cauchy_scale_px, DirectChainJacobian{{ToPoseParams(T_mount_holder)}}, free_intrinsics);
}

ceres::CostFunction* ViewCrossReprojectionError::Create(const Camera& camera_k, const Eigen::Isometry3d& T_mount_holder,
                                                        ViewPoints points, double cauchy_scale_px) {
  return new ChainedViewCost<3, CrossChainJacobian>(camera_k, std::make_shared<const ViewPoints>(std::move(points)),
                                                    cauchy_scale_px,
                                                    CrossChainJacobian{{ToPoseParams(T_mount_holder)}});
}

}  // namespace handeye
