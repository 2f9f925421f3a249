// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// How the solver moves a pose block.

#include <ceres/manifold.h>
#include <ceres/product_manifold.h>

namespace handeye::internal {

/// Ceres' manifold of a pose block `[qx qy qz qw tx ty tz]`: the quaternion's
/// 3-dimensional tangent, then the translation.
using PoseManifold =
    ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>;

}  // namespace handeye::internal
