// SPDX-License-Identifier: GPL-2.0-or-later
// The hand-derived derivatives of core/src/cost_jacobians.h and the camera
// model's ProjectWithJacobian, each against ceres' autodiff of the same
// formula (the view costs that chain them are checked in cost_functions_test).
#include <catch2/catch.hpp>
#include <ceres/jet.h>

#include <cmath>

#include "cost_jacobians.h"
#include "handeye/core/transform.h"
#include "support/distorted_camera.h"

// In the namespace of what it tests: a using-directive would reach the files a
// unity build compiles after this one.
namespace handeye::cost_internal {

TEST_CASE("ComposeJacobians is the derivative of Compose in all 14 coordinates", "[cost][jacobian]") {
  // Off the unit sphere on purpose: Ceres asks for all 7 block coordinates.
  PoseParams a = ToPoseParams(MakeTransformFromRotationVector({0.3, -1.2, 0.5}, {0.2, -0.4, 1.1}));
  const PoseParams b = ToPoseParams(MakeTransformFromRotationVector({-0.7, 0.1, 2.0}, {-0.3, 0.5, 0.25}));
  a[0] *= 1.01;
  using Jet = ceres::Jet<double, 14>;
  Jet ja[7], jb[7], out[7];
  for (int i = 0; i < 7; ++i) {
    ja[i] = Jet(a[i], i);
    jb[i] = Jet(b[i], 7 + i);
  }
  Compose(ja, jb, out);
  Matrix7 d_a, d_b;
  ComposeJacobians(a.data(), b.data(), &d_a, &d_b);
  double worst = 0;
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 7; ++c) {
      worst = std::max(worst, std::abs(d_a(r, c) - out[r].v[c]));
      worst = std::max(worst, std::abs(d_b(r, c) - out[r].v[7 + c]));
    }
  CHECK(worst < 1e-12);
}

TEST_CASE("ApplyCauchy scales like ProjectPoint and has its derivative", "[cost][jacobian]") {
  for (double a : {0.0, 0.5, 2.0})
    for (const Eigen::Vector2d& r0 : {Eigen::Vector2d(0.3, -0.2), Eigen::Vector2d(4.0, 7.5), Eigen::Vector2d(1e-6, 0)}) {
      INFO("scale " << a << " residual " << r0.transpose());
      using Jet = ceres::Jet<double, 2>;
      // ProjectPoint's scaling of the same residual, through jets.
      Jet x = Jet(r0.x(), 0), y = Jet(r0.y(), 1);
      if (a > 0) {
        const Jet s = (x * x + y * y) / Jet(a * a);
        const Jet ratio = s < Jet(1e-8) ? Jet(1.0) - s / Jet(2.0) + s * s / Jet(3.0) : log1p(s) / s;
        x *= sqrt(ratio);
        y *= sqrt(ratio);
      }
      Eigen::Vector2d r = r0;
      const Eigen::Matrix2d d = ApplyCauchy(a, &r);
      CHECK(r.x() == Approx(x.a).margin(1e-15));
      CHECK(r.y() == Approx(y.a).margin(1e-15));
      CHECK(std::abs(d(0, 0) - x.v[0]) + std::abs(d(0, 1) - x.v[1]) + std::abs(d(1, 0) - y.v[0]) +
                std::abs(d(1, 1) - y.v[1]) <
            1e-9);
    }
}

TEST_CASE("The camera model's ProjectWithJacobian: Project's pixel and its derivative", "[camera][jacobian]") {
  const Camera camera = test::DistortedCamera();
  IntrinsicsJet2 params;
  for (int k = 0; k < OpenCVCameraModel::kNumParams; ++k) params[k] = ceres::Jet<double, 2>(camera.params[k]);
  using Jet = ceres::Jet<double, 3>;
  Jet jet_params[OpenCVCameraModel::kNumParams];
  for (int k = 0; k < OpenCVCameraModel::kNumParams; ++k) jet_params[k] = Jet(camera.params[k]);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.1, -0.2, 1.5), Eigen::Vector3d(-0.9, 0.4, 1.1)}) {
    double uv[2];
    Eigen::Matrix<double, 2, 3> d;
    REQUIRE(OpenCVCameraModel::ProjectWithJacobian(params.data(), p.data(), uv, &d));
    const Jet p_jet[3] = {Jet(p.x(), 0), Jet(p.y(), 1), Jet(p.z(), 2)};
    Jet uv_jet[2];
    REQUIRE(OpenCVCameraModel::Project(jet_params, p_jet, uv_jet));
    for (int r = 0; r < 2; ++r) {
      CHECK(uv[r] == Approx(uv_jet[r].a).epsilon(1e-15));
      for (int c = 0; c < 3; ++c) CHECK(d(r, c) == Approx(uv_jet[r].v[c]).epsilon(1e-12).margin(1e-9));
    }
  }
  const double behind[3] = {0.1, 0.1, -1.0};
  double uv[2];
  Eigen::Matrix<double, 2, 3> d;
  CHECK_FALSE(OpenCVCameraModel::ProjectWithJacobian(params.data(), behind, uv, &d));
}

}  // namespace handeye::cost_internal
