// SPDX-License-Identifier: GPL-2.0-or-later
// The cost functions the solver uses: the view costs with hand-chained
// derivatives (cost_jacobians.h) and the robot pose prior.
#include "handeye/core/cost_functions.h"

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

ceres::CostFunction* ViewReprojectionError::Create(const Camera& camera, const Eigen::Isometry3d& M, ViewPoints points,
                                                   double cauchy_scale_px) {
  return Create(camera, M, std::make_shared<const ViewPoints>(std::move(points)), cauchy_scale_px);
}

ceres::CostFunction* ViewReprojectionError::Create(const Camera& camera, const Eigen::Isometry3d& M,
                                                   std::shared_ptr<const ViewPoints> points, double cauchy_scale_px,
                                                   bool free_intrinsics) {
  return new ChainedViewCost<2, DirectChainJacobian>(camera, std::move(points), cauchy_scale_px,
                                                     DirectChainJacobian{{ToPoseParams(M)}}, free_intrinsics);
}

ceres::CostFunction* ViewCrossReprojectionError::Create(const Camera& camera_k, const Eigen::Isometry3d& M,
                                                        ViewPoints points, double cauchy_scale_px) {
  return new ChainedViewCost<3, CrossChainJacobian>(camera_k, std::make_shared<const ViewPoints>(std::move(points)),
                                                    cauchy_scale_px, CrossChainJacobian{{ToPoseParams(M)}});
}

}  // namespace handeye
