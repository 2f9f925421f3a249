// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The camera of the cost-function and Jacobian tests (test_core).

#include <string>

#include "handeye/core/camera.h"

namespace handeye::test {

/// 1920×1080, fx ≠ fy, the principal point off centre and all five
/// distortion coefficients non-zero, so every intrinsic reaches the residual.
inline Camera DistortedCamera() {
  std::string why;
  return *Camera::Make("cam", 1920, 1080, 1400, 1395, 955, 545, {-0.1, 0.03, 0.001, -0.002, 0.004},
                       &why);
}

}  // namespace handeye::test
