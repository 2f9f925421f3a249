// SPDX-License-Identifier: GPL-2.0-or-later
// clang-format off
// Before Catch, so that CHECK is Catch's, not glog's (which Ceres' headers define).
#include "cost_functions.h"
// clang-format on
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <utility>

#include "support/distorted_camera.h"

// glog (through Ceres) defines its own CHECK; this file uses Catch's REQUIRE.

using namespace handeye;

namespace {

// The reference each cost's Create() is checked against: ceres'
// autodiff of the functor's templated operator().
ceres::CostFunction* AutoDiff(const Camera& camera, const Eigen::Isometry3d& M, ViewPoints points,
                              double a) {
  const int residuals = 2 * static_cast<int>(points.p_target.size());
  return new ceres::AutoDiffCostFunction<ViewReprojectionError, ceres::DYNAMIC, 7, 7>(
      new ViewReprojectionError(camera, M, std::move(points), a), residuals);
}

ceres::CostFunction* AutoDiffWithIntrinsics(const Camera& camera, const Eigen::Isometry3d& M,
                                            ViewPoints points, double a) {
  const int residuals = 2 * static_cast<int>(points.p_target.size());
  return new ceres::AutoDiffCostFunction<ViewReprojectionError, ceres::DYNAMIC, 7, 7,
                                         OpenCVCameraModel::kNumParams>(
      new ViewReprojectionError(camera, M, std::move(points), a), residuals);
}

ceres::CostFunction* AutoDiffCross(const Camera& camera_k, const Eigen::Isometry3d& M,
                                   ViewPoints points, double a) {
  const int residuals = 2 * static_cast<int>(points.p_target.size());
  return new ceres::AutoDiffCostFunction<ViewCrossReprojectionError, ceres::DYNAMIC, 7, 7, 7>(
      new ViewCrossReprojectionError(camera_k, M, std::move(points), a), residuals);
}

ceres::CostFunction* AutoDiffWithRobot(const Camera& camera, ViewPoints points, double a) {
  const int residuals = 2 * static_cast<int>(points.p_target.size());
  return new ceres::AutoDiffCostFunction<ViewReprojectionWithRobotError, ceres::DYNAMIC, 7, 7, 7>(
      new ViewReprojectionWithRobotError{camera.params, std::move(points), a}, residuals);
}

struct Chain {
  Eigen::Isometry3d X = MakeTransformFromRotationVector({0.1, -2.9, 0.2}, {0.3, 0.8, 2.1});
  Eigen::Isometry3d M = MakeTransformFromRotationVector({0.4, 0.2, -0.3}, {0.5, 0.1, 1.0});
  Eigen::Isometry3d Z = MakeTransformFromRotationVector({-0.2, 0.1, 0.0}, {0.0, 0.02, 0.1});
  Eigen::Isometry3d X_t = MakeTransformFromRotationVector({0.3, 2.0, -0.1}, {-0.5, 0.6, 2.5});
};

/// Points in front of the camera with offsets of 0.7/−1.1 px, 3 px and 40 px.
ViewPoints Offsets(const Camera& camera, const Chain& c, std::vector<Eigen::Vector2d>* offsets) {
  *offsets = {{0.7, -1.1}, {3.0, 0.0}, {0.0, 40.0}};
  const std::vector<Eigen::Vector3d> p = {{0.08, 0.12, 0.0}, {0.0, 0.0, 0.0}, {0.16, 0.04, 0.0}};
  ViewPoints view;
  for (size_t i = 0; i < p.size(); ++i) {
    const auto uv = camera.Project(c.X * c.M * c.Z * p[i]);
    REQUIRE(uv);
    view.p_target.push_back(p[i]);
    view.observed_px.push_back(*uv - (*offsets)[i]);
  }
  return view;
}

// Central differences of CostFunction::Evaluate against its autodiff
// Jacobians, every parameter of every block.
double WorstJacobianError(const ceres::CostFunction& cost, std::vector<PoseParams> blocks) {
  const size_t n = blocks.size();
  const int m = cost.num_residuals();
  std::vector<double*> params;
  for (auto& b : blocks) params.push_back(b.data());
  std::vector<std::vector<double>> jac(n, std::vector<double>(m * 7));
  std::vector<double*> jac_ptrs;
  for (auto& j : jac) jac_ptrs.push_back(j.data());
  std::vector<double> r(m), rp(m), rm(m);
  if (!cost.Evaluate(params.data(), r.data(), jac_ptrs.data())) return 1e300;
  double worst = 0;
  for (size_t b = 0; b < n; ++b)
    for (int i = 0; i < 7; ++i) {
      const double h = 1e-6;
      const double saved = blocks[b][i];
      blocks[b][i] = saved + h;
      cost.Evaluate(params.data(), rp.data(), nullptr);
      blocks[b][i] = saved - h;
      cost.Evaluate(params.data(), rm.data(), nullptr);
      blocks[b][i] = saved;
      for (int k = 0; k < m; ++k) {
        const double numeric = (rp[k] - rm[k]) / (2 * h);
        const double analytic = jac[b][k * 7 + i];
        worst = std::max(worst, std::abs(numeric - analytic) / std::max(1.0, std::abs(analytic)));
      }
    }
  return worst;
}

}  // namespace

TEST_CASE("View reprojection gives the exact residuals of the chain", "[cost]") {
  const Camera camera = test::DistortedCamera();
  const Chain c;
  std::vector<Eigen::Vector2d> offsets;
  const ViewPoints view = Offsets(camera, c, &offsets);
  std::unique_ptr<ceres::CostFunction> plain(ViewReprojectionError::Create(camera, c.M, view, 0.0));
  REQUIRE(plain->num_residuals() == 6);
  PoseParams X = ToPoseParams(c.X), Z = ToPoseParams(c.Z);
  const double* params[] = {X.data(), Z.data()};
  double r[6];
  REQUIRE(plain->Evaluate(params, r, nullptr));
  for (size_t i = 0; i < offsets.size(); ++i) {
    REQUIRE(r[2 * i] == Approx(offsets[i].x()).margin(1e-8));
    REQUIRE(r[2 * i + 1] == Approx(offsets[i].y()).margin(1e-8));
  }

  // Cross term: T_camk_camt · X_t reproduces X_k.
  std::unique_ptr<ceres::CostFunction> cross(
      ViewCrossReprojectionError::Create(camera, c.M, view, 0.0));
  PoseParams T_kt = ToPoseParams(c.X * c.X_t.inverse()), Xt = ToPoseParams(c.X_t);
  const double* cross_params[] = {T_kt.data(), Xt.data(), Z.data()};
  REQUIRE(cross->Evaluate(cross_params, r, nullptr));
  for (size_t i = 0; i < offsets.size(); ++i) {
    REQUIRE(r[2 * i] == Approx(offsets[i].x()).margin(1e-7));
    REQUIRE(r[2 * i + 1] == Approx(offsets[i].y()).margin(1e-7));
  }
}

TEST_CASE("The robust residuals square to the per-point Cauchy cost", "[cost]") {
  const Camera camera = test::DistortedCamera();
  const Chain c;
  std::vector<Eigen::Vector2d> offsets;
  const ViewPoints view = Offsets(camera, c, &offsets);
  for (double a : {0.5, 1.0, 4.0}) {
    std::unique_ptr<ceres::CostFunction> robust(
        ViewReprojectionError::Create(camera, c.M, view, a));
    PoseParams X = ToPoseParams(c.X), Z = ToPoseParams(c.Z);
    const double* params[] = {X.data(), Z.data()};
    double r[6];
    REQUIRE(robust->Evaluate(params, r, nullptr));
    for (size_t i = 0; i < offsets.size(); ++i) {
      const double s = offsets[i].squaredNorm();
      const double rho = a * a * std::log1p(s / (a * a));
      REQUIRE(r[2 * i] * r[2 * i] + r[2 * i + 1] * r[2 * i + 1] == Approx(rho).epsilon(1e-12));
      // Same direction as the plain residual.
      REQUIRE(r[2 * i] * offsets[i].y() - r[2 * i + 1] * offsets[i].x() ==
              Approx(0.0).margin(1e-9));
    }
  }
}

TEST_CASE("Cost functor derivatives agree with central differences", "[cost]") {
  const Camera camera = test::DistortedCamera();
  const Chain c;
  std::vector<Eigen::Vector2d> offsets;
  const ViewPoints view = Offsets(camera, c, &offsets);
  for (double a : {0.0, 1.0}) {
    std::unique_ptr<ceres::CostFunction> rpj(ViewReprojectionError::Create(camera, c.M, view, a));
    const double rpj_error = WorstJacobianError(*rpj, {ToPoseParams(c.X), ToPoseParams(c.Z)});
    INFO("cauchy scale " << a << ", reprojection: worst relative Jacobian error " << rpj_error);
    REQUIRE(rpj_error < 1e-5);
    std::unique_ptr<ceres::CostFunction> cross(
        ViewCrossReprojectionError::Create(camera, c.M, view, a));
    const double cross_error = WorstJacobianError(
        *cross, {ToPoseParams(c.X * c.X_t.inverse()), ToPoseParams(c.X_t), ToPoseParams(c.Z)});
    INFO("cross: worst relative Jacobian error " << cross_error);
    REQUIRE(cross_error < 1e-5);
  }
}

// Largest |a − b| over residuals and Jacobians of two cost functions.
// Residuals and Jacobians of two costs over blocks of any size: the largest difference.
double WorstDifferenceAnySize(const ceres::CostFunction& a, const ceres::CostFunction& b,
                              std::vector<std::vector<double>> blocks) {
  const int m = a.num_residuals();
  std::vector<double*> params;
  for (auto& block : blocks) params.push_back(block.data());
  std::vector<double> ra(m), rb(m);
  std::vector<std::vector<double>> ja, jb;
  for (const auto& block : blocks) ja.emplace_back(m * block.size());
  jb = ja;
  std::vector<double*> pa, pb;
  for (size_t i = 0; i < blocks.size(); ++i) {
    pa.push_back(ja[i].data());
    pb.push_back(jb[i].data());
  }
  if (!a.Evaluate(params.data(), ra.data(), pa.data()) ||
      !b.Evaluate(params.data(), rb.data(), pb.data()))
    return 1e300;
  double worst = 0;
  for (int i = 0; i < m; ++i) worst = std::max(worst, std::abs(ra[i] - rb[i]));
  for (size_t k = 0; k < blocks.size(); ++k)
    for (size_t i = 0; i < ja[k].size(); ++i)
      worst = std::max(worst, std::abs(ja[k][i] - jb[k][i]));
  return worst;
}

double WorstDifference(const ceres::CostFunction& a, const ceres::CostFunction& b,
                       const std::vector<PoseParams>& blocks) {
  std::vector<std::vector<double>> any;
  for (const auto& block : blocks) any.emplace_back(block.begin(), block.end());
  return WorstDifferenceAnySize(a, b, any);
}

TEST_CASE("Chain-rule derivatives equal autodiff over every parameter", "[cost]") {
  const Camera camera = test::DistortedCamera();
  const Chain c;
  std::vector<Eigen::Vector2d> offsets;
  const ViewPoints view = Offsets(camera, c, &offsets);
  for (double a : {0.0, 1.0}) {
    std::unique_ptr<ceres::CostFunction> fast(ViewReprojectionError::Create(camera, c.M, view, a));
    std::unique_ptr<ceres::CostFunction> reference(AutoDiff(camera, c.M, view, a));
    REQUIRE(WorstDifference(*fast, *reference, {ToPoseParams(c.X), ToPoseParams(c.Z)}) < 1e-9);
    std::unique_ptr<ceres::CostFunction> fast_cross(
        ViewCrossReprojectionError::Create(camera, c.M, view, a));
    std::unique_ptr<ceres::CostFunction> reference_cross(AutoDiffCross(camera, c.M, view, a));
    REQUIRE(WorstDifference(*fast_cross, *reference_cross,
                            {ToPoseParams(c.X * c.X_t.inverse()), ToPoseParams(c.X_t),
                             ToPoseParams(c.Z)}) < 1e-9);
  }
}

TEST_CASE("A residual of zero keeps finite derivatives under the robust loss", "[cost]") {
  const Camera camera = test::DistortedCamera();
  const Chain c;
  ViewPoints view;
  view.p_target = {{0.05, 0.05, 0.0}};
  view.observed_px = {*camera.Project(c.X * c.M * c.Z * view.p_target[0])};
  std::unique_ptr<ceres::CostFunction> robust(
      ViewReprojectionError::Create(camera, c.M, view, 1.0));
  PoseParams X = ToPoseParams(c.X), Z = ToPoseParams(c.Z);
  const double* params[] = {X.data(), Z.data()};
  double r[2], jx[14], jz[14];
  double* jac[] = {jx, jz};
  REQUIRE(robust->Evaluate(params, r, jac));
  for (double v : jx) REQUIRE(std::isfinite(v));
  for (double v : jz) REQUIRE(std::isfinite(v));
}

TEST_CASE("Chain-rule derivatives equal autodiff with every distortion term", "[cost]") {
  // Rational, thin-prism and tilted-sensor terms all go through the
  // per-point distortion jets of the fast path.
  std::string why;
  const auto camera = Camera::Make("full", 1920, 1080, 1400, 1395, 955, 545,
                                   {-0.1, 0.03, 0.001, -0.002, 0.004, 0.02, -0.01, 0.005, 0.001,
                                    -0.0005, 0.0008, 0.0002, 0.01, -0.02},
                                   &why);
  REQUIRE(camera);
  const Chain c;
  std::vector<Eigen::Vector2d> offsets;
  const ViewPoints view = Offsets(*camera, c, &offsets);
  const auto shared = std::make_shared<const ViewPoints>(view);
  for (double a : {0.0, 1.0}) {
    std::unique_ptr<ceres::CostFunction> fast(
        ViewReprojectionError::Create(*camera, c.M, shared, a));
    std::unique_ptr<ceres::CostFunction> reference(AutoDiff(*camera, c.M, view, a));
    REQUIRE(WorstDifference(*fast, *reference, {ToPoseParams(c.X), ToPoseParams(c.Z)}) < 1e-9);
    std::unique_ptr<ceres::CostFunction> fast_cross(
        ViewCrossReprojectionError::Create(*camera, c.M, view, a));
    std::unique_ptr<ceres::CostFunction> reference_cross(AutoDiffCross(*camera, c.M, view, a));
    REQUIRE(WorstDifference(*fast_cross, *reference_cross,
                            {ToPoseParams(c.X * c.X_t.inverse()), ToPoseParams(c.X_t),
                             ToPoseParams(c.Z)}) < 1e-9);
  }
}

TEST_CASE("The cross term is the reprojection term in Y = T_camk_camt · X_t", "[cost]") {
  // The joint solve relies on this to optimise Y_kt instead of T_camk_camt.
  const Camera camera = test::DistortedCamera();
  const Chain c;
  std::vector<Eigen::Vector2d> offsets;
  const ViewPoints view = Offsets(camera, c, &offsets);
  // A pair transform that does not reproduce X_k, so the residuals are not small.
  const Eigen::Isometry3d T_kt =
      MakeTransformFromRotationVector({0.01, -0.02, 0.03}, {0.01, 0.0, -0.02}) * c.X *
      c.X_t.inverse();
  for (double a : {0.0, 1.0}) {
    std::unique_ptr<ceres::CostFunction> cross(
        ViewCrossReprojectionError::Create(camera, c.M, view, a));
    std::unique_ptr<ceres::CostFunction> direct(
        ViewReprojectionError::Create(camera, c.M, view, a));
    PoseParams T = ToPoseParams(T_kt), Xt = ToPoseParams(c.X_t), Z = ToPoseParams(c.Z);
    PoseParams Y = ToPoseParams(T_kt * c.X_t);
    const double* cross_params[] = {T.data(), Xt.data(), Z.data()};
    const double* direct_params[] = {Y.data(), Z.data()};
    double r_cross[6], r_direct[6];
    REQUIRE(cross->Evaluate(cross_params, r_cross, nullptr));
    REQUIRE(direct->Evaluate(direct_params, r_direct, nullptr));
    for (int i = 0; i < 6; ++i) {
      REQUIRE(std::abs(r_direct[i]) > 0.1);
      REQUIRE(r_cross[i] == Approx(r_direct[i]).epsilon(1e-9));
    }
  }
}

TEST_CASE("The cost with the robot pose as a block: derivatives and values", "[cost]") {
  const Camera camera = test::DistortedCamera();
  const Chain c;
  std::vector<Eigen::Vector2d> offsets;
  const ViewPoints view = Offsets(camera, c, &offsets);
  for (double a : {0.0, 1.0}) {
    std::unique_ptr<ceres::CostFunction> fast(ViewReprojectionWithRobotError::Create(
        camera, std::make_shared<const ViewPoints>(view), a));
    std::unique_ptr<ceres::CostFunction> reference(AutoDiffWithRobot(camera, view, a));
    const std::vector<PoseParams> blocks = {ToPoseParams(c.X), ToPoseParams(c.M),
                                            ToPoseParams(c.Z)};
    REQUIRE(WorstDifference(*fast, *reference, blocks) < 1e-9);
    REQUIRE(WorstJacobianError(*fast, blocks) < 1e-5);
    // With the robot pose as given, the same residuals as the fixed-M cost.
    std::unique_ptr<ceres::CostFunction> fixed(ViewReprojectionError::Create(camera, c.M, view, a));
    PoseParams X = blocks[0], M = blocks[1], Z = blocks[2];
    const double* with_m[] = {X.data(), M.data(), Z.data()};
    const double* without_m[] = {X.data(), Z.data()};
    double r_with[6], r_without[6];
    REQUIRE(fast->Evaluate(with_m, r_with, nullptr));
    REQUIRE(fixed->Evaluate(without_m, r_without, nullptr));
    for (int i = 0; i < 6; ++i) REQUIRE(r_with[i] == Approx(r_without[i]).margin(1e-9));
  }
}

TEST_CASE("The robot pose prior weighs rotation and displacement by their sigma", "[cost]") {
  const Eigen::Isometry3d reported =
      MakeTransformFromRotationVector({0.4, 0.2, -0.3}, {0.5, 0.1, 1.0});
  // The flange 2 mm off along x and turned 0.1° about z (base frame, about the flange).
  Eigen::Isometry3d moved = reported;
  moved.linear() =
      Eigen::AngleAxisd(0.1 * M_PI / 180.0, Eigen::Vector3d::UnitZ()) * reported.linear();
  moved.translation().x() += 0.002;
  for (bool inverse : {false, true}) {
    std::unique_ptr<ceres::CostFunction> prior(
        RobotPosePrior::Create(reported, inverse, 0.05 * M_PI / 180.0, 0.001, 0.2));
    PoseParams M = ToPoseParams(inverse ? moved.inverse() : moved);
    const double* params[] = {M.data()};
    double r[6];
    REQUIRE(prior->Evaluate(params, r, nullptr));
    // 0.1° over σ 0.05° and 2 mm over σ 1 mm, times the pixel σ 0.2.
    REQUIRE(r[0] == Approx(0.0).margin(1e-9));
    REQUIRE(r[1] == Approx(0.0).margin(1e-9));
    REQUIRE(r[2] == Approx(0.4).epsilon(1e-6));
    REQUIRE(r[3] == Approx(0.4).epsilon(1e-9));
    REQUIRE(r[4] == Approx(0.0).margin(1e-9));
    REQUIRE(r[5] == Approx(0.0).margin(1e-9));
    REQUIRE(WorstJacobianError(*prior, {M}) < 1e-5);
  }
}

namespace {

std::vector<double> IntrinsicsBlock(const Camera& camera) {
  return {camera.params.begin(), camera.params.end()};
}

}  // namespace

TEST_CASE("With the intrinsics as unknowns, chain-rule derivatives equal autodiff",
          "[cost][intrinsics]") {
  std::string why;
  const auto rational = Camera::Make(
      "rational", 1920, 1080, 1400, 1395, 955, 545,
      {-0.1, 0.03, 0.001, -0.002, 0.004, 0.02, -0.01, 0.005, 0.001, -0.0005, 0.0008, 0.0002}, &why);
  REQUIRE(rational);
  for (const Camera& camera : {test::DistortedCamera(), *rational}) {
    const Chain c;
    std::vector<Eigen::Vector2d> offsets;
    const ViewPoints view = Offsets(camera, c, &offsets);
    for (double a : {0.0, 1.0}) {
      std::unique_ptr<ceres::CostFunction> fast(ViewReprojectionError::Create(
          camera, c.M, std::make_shared<const ViewPoints>(view), a, true));
      std::unique_ptr<ceres::CostFunction> reference(AutoDiffWithIntrinsics(camera, c.M, view, a));
      REQUIRE(fast->parameter_block_sizes().size() == 3);
      const PoseParams X = ToPoseParams(c.X), Z = ToPoseParams(c.Z);
      CHECK(WorstDifferenceAnySize(
                *fast, *reference,
                {{X.begin(), X.end()}, {Z.begin(), Z.end()}, IntrinsicsBlock(camera)}) < 1e-9);
    }
  }
}

TEST_CASE("The intrinsics derivatives agree with central differences", "[cost][intrinsics]") {
  const Camera camera = test::DistortedCamera();
  const Chain c;
  std::vector<Eigen::Vector2d> offsets;
  const ViewPoints view = Offsets(camera, c, &offsets);
  std::unique_ptr<ceres::CostFunction> cost(ViewReprojectionError::Create(
      camera, c.M, std::make_shared<const ViewPoints>(view), 1.0, true));
  PoseParams X = ToPoseParams(c.X), Z = ToPoseParams(c.Z);
  std::vector<double> K = IntrinsicsBlock(camera);
  const int m = cost->num_residuals();
  const double* params[] = {X.data(), Z.data(), K.data()};
  std::vector<double> r(m), rp(m), rm(m), jk(m * OpenCVCameraModel::kNumParams);
  double* jac[] = {nullptr, nullptr, jk.data()};
  REQUIRE(cost->Evaluate(params, r.data(), jac));
  // fx … k6, s1 … s4 (the tilt angles enter only when non-zero).
  for (int p = 0; p < 16; ++p) {
    const double h = p < 4 ? 1e-4 : 1e-7;
    const double saved = K[p];
    K[p] = saved + h;
    REQUIRE(cost->Evaluate(params, rp.data(), nullptr));
    K[p] = saved - h;
    REQUIRE(cost->Evaluate(params, rm.data(), nullptr));
    K[p] = saved;
    for (int i = 0; i < m; ++i) {
      const double numeric = (rp[i] - rm[i]) / (2 * h);
      const double analytic = jk[i * OpenCVCameraModel::kNumParams + p];
      CHECK(std::abs(numeric - analytic) <= 1e-5 * std::max(1.0, std::abs(analytic)));
    }
  }
}
