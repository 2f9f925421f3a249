// SPDX-License-Identifier: GPL-2.0-or-later
#include <catch2/catch.hpp>
#include <array>
#include <memory>

#include "handeye/core/cost_functions.h"

// glog (through Ceres) defines its own CHECK; this file uses Catch's REQUIRE.

using namespace handeye;

namespace {

Camera TestCamera() {
  std::string why;
  return *Camera::Make("cam", 1920, 1080, 1400, 1395, 955, 545, {-0.1, 0.03, 0.001, -0.002, 0.004}, &why);
}

}  // namespace

TEST_CASE("ReprojectionError gives the exact residual of the chain", "[cost]") {
  const Camera camera = TestCamera();
  const Eigen::Isometry3d X = MakeTransformFromRotationVector({0.1, -2.9, 0.2}, {0.3, 0.8, 2.1});
  const Eigen::Isometry3d M = MakeTransformFromRotationVector({0.4, 0.2, -0.3}, {0.5, 0.1, 1.0});
  const Eigen::Isometry3d Z = MakeTransformFromRotationVector({-0.2, 0.1, 0.0}, {0.0, 0.02, 0.1});
  const Eigen::Vector3d p(0.08, 0.12, 0.0);
  const auto uv = camera.Project(X * M * Z * p);
  REQUIRE(uv);
  const Eigen::Vector2d observed = *uv + Eigen::Vector2d(0.7, -1.1);
  ReprojectionError functor(camera, M, p, observed);
  const PoseParams Xp = ToPoseParams(X), Zp = ToPoseParams(Z);
  double r[2];
  REQUIRE(functor(Xp.data(), Zp.data(), r));
  REQUIRE(r[0] == Approx(-0.7).margin(1e-9));
  REQUIRE(r[1] == Approx(1.1).margin(1e-9));

  // Cross term: T_camk_camt · X_t reproduces X_k.
  const Eigen::Isometry3d X_t = MakeTransformFromRotationVector({0.3, 2.0, -0.1}, {-0.5, 0.6, 2.5});
  const PoseParams T_kt = ToPoseParams(X * X_t.inverse()), Xt = ToPoseParams(X_t);
  CrossReprojectionError cross(camera, M, p, observed);
  REQUIRE(cross(T_kt.data(), Xt.data(), Zp.data(), r));
  REQUIRE(r[0] == Approx(-0.7).margin(1e-8));
  REQUIRE(r[1] == Approx(1.1).margin(1e-8));
}

// Central differences of CostFunction::Evaluate against its autodiff
// Jacobians, every parameter of every block. (ceres::GradientChecker of the
// Debian Ceres 2.1 build fails its own numeric evaluation on these functors,
// so the same comparison is made here directly.)
double WorstJacobianError(const ceres::CostFunction& cost, std::vector<PoseParams> blocks) {
  const size_t n = blocks.size();
  std::vector<double*> params;
  for (auto& b : blocks) params.push_back(b.data());
  std::vector<std::array<double, 14>> jac(n);
  std::vector<double*> jac_ptrs;
  for (auto& j : jac) jac_ptrs.push_back(j.data());
  double r[2];
  if (!cost.Evaluate(params.data(), r, jac_ptrs.data())) return 1e300;
  double worst = 0;
  for (size_t b = 0; b < n; ++b)
    for (int i = 0; i < 7; ++i) {
      const double h = 1e-6;
      const double saved = blocks[b][i];
      double rp[2], rm[2];
      blocks[b][i] = saved + h;
      cost.Evaluate(params.data(), rp, nullptr);
      blocks[b][i] = saved - h;
      cost.Evaluate(params.data(), rm, nullptr);
      blocks[b][i] = saved;
      for (int k = 0; k < 2; ++k) {
        const double numeric = (rp[k] - rm[k]) / (2 * h);
        const double analytic = jac[b][k * 7 + i];
        worst = std::max(worst, std::abs(numeric - analytic) / std::max(1.0, std::abs(analytic)));
      }
    }
  return worst;
}

TEST_CASE("Cost functor derivatives agree with central differences", "[cost]") {
  const Camera camera = TestCamera();
  const Eigen::Isometry3d X = MakeTransformFromRotationVector({0.1, -2.9, 0.2}, {0.3, 0.8, 2.1});
  const Eigen::Isometry3d M = MakeTransformFromRotationVector({0.4, 0.2, -0.3}, {0.5, 0.1, 1.0});
  const Eigen::Isometry3d Z = MakeTransformFromRotationVector({-0.2, 0.1, 0.0}, {0.0, 0.02, 0.1});
  const Eigen::Isometry3d X_t = MakeTransformFromRotationVector({0.3, 2.0, -0.1}, {-0.5, 0.6, 2.5});
  const Eigen::Vector3d p(0.08, 0.12, 0.0);
  std::unique_ptr<ceres::CostFunction> rpj(ReprojectionError::Create(camera, M, p, {900, 500}));
  const double rpj_error = WorstJacobianError(*rpj, {ToPoseParams(X), ToPoseParams(Z)});
  INFO("reprojection: worst relative Jacobian error " << rpj_error);
  REQUIRE(rpj_error < 1e-5);
  std::unique_ptr<ceres::CostFunction> cross(CrossReprojectionError::Create(camera, M, p, {900, 500}));
  const double cross_error =
      WorstJacobianError(*cross, {ToPoseParams(X * X_t.inverse()), ToPoseParams(X_t), ToPoseParams(Z)});
  INFO("cross: worst relative Jacobian error " << cross_error);
  REQUIRE(cross_error < 1e-5);
}
