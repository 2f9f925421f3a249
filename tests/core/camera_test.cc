// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/camera.h"

#include <ceres/jet.h>

#include <catch2/catch.hpp>
#include <opencv2/calib3d.hpp>
#include <random>

using namespace handeye;

namespace {

Camera MakeCamera(const std::vector<double>& dist) {
  std::string why;
  auto cam = Camera::Make("cam0", 1920, 1080, 1371.02, 1369.5, 960.5, 540.5, dist, &why);
  REQUIRE(cam);
  return *cam;
}

const std::vector<std::vector<double>> kDistortions = {
    {},
    {-0.12, 0.05, 0.001, -0.0007},
    {-0.12, 0.05, 0.001, -0.0007, -0.01},
    {-0.12, 0.05, 0.001, -0.0007, -0.01, 0.02, -0.01, 0.003},
    {-0.12, 0.05, 0.001, -0.0007, -0.01, 0.02, -0.01, 0.003, 0.001, -0.0005, 0.0008, 0.0002},
    {-0.12, 0.05, 0.001, -0.0007, -0.01, 0.02, -0.01, 0.003, 0.001, -0.0005, 0.0008, 0.0002, 0.01,
     -0.02},
};

}  // namespace

TEST_CASE("Project agrees with cv::projectPoints to 1e-9 px for every coefficient count",
          "[camera]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> xy(-0.6, 0.6), z(0.5, 5.0);
  for (const auto& dist : kDistortions) {
    const Camera cam = MakeCamera(dist);
    std::vector<cv::Point3d> pts;
    for (int i = 0; i < 200; ++i) {
      const double d = z(rng);
      pts.emplace_back(xy(rng) * d, xy(rng) * d * 0.6, d);
    }
    const cv::Matx33d K(cam.fx(), 0, cam.cx(), 0, cam.fy(), cam.cy(), 0, 0, 1);
    std::vector<cv::Point2d> cv_px;
    cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, dist, cv_px);
    double worst = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
      const auto uv = cam.Project({pts[i].x, pts[i].y, pts[i].z});
      REQUIRE(uv);
      worst = std::max(worst, (*uv - Eigen::Vector2d(cv_px[i].x, cv_px[i].y)).norm());
    }
    INFO("coefficients: " << dist.size() << ", worst difference " << worst << " px");
    CHECK(worst < 1e-9);
  }
}

TEST_CASE("Undistort inverts Project", "[camera]") {
  for (const auto& dist : kDistortions) {
    const Camera cam = MakeCamera(dist);
    for (double x = -0.6; x <= 0.6; x += 0.1)
      for (double y = -0.35; y <= 0.35; y += 0.07) {
        const auto uv = cam.Project({x, y, 1.0});
        REQUIRE(uv);
        const auto back = cam.Undistort(*uv);
        REQUIRE(back);
        CHECK((*back - Eigen::Vector2d(x, y)).norm() < 1e-10);
      }
  }
}

TEST_CASE("Camera::Make rejects bad intrinsics", "[camera]") {
  std::string why;
  CHECK_FALSE(Camera::Make("c", 640, 480, 500, 500, 320, 240, {0.1, 0.2, 0.3}, &why));
  CHECK(why.find("0, 4, 5, 8, 12 or 14") != std::string::npos);
  CHECK_FALSE(Camera::Make("c", 640, 480, -1, 500, 320, 240, {}, &why));
  CHECK_FALSE(Camera::Make("c", 0, 480, 500, 500, 320, 240, {}, &why));
  CHECK_FALSE(Camera::Make("c", 640, 480, 500, 500, 320, 240, {0, 0, 0, std::nan("")}, &why));
  CHECK(Camera::Make("c", 640, 480, 500, 500, 320, 240, {0, 0, 0, 0}, &why));
}

TEST_CASE("Project refuses points behind the camera", "[camera]") {
  const Camera cam = MakeCamera({});
  CHECK_FALSE(cam.Project({0, 0, -1}));
  CHECK_FALSE(cam.Project({0, 0, 0}));
}

TEST_CASE(
    "ProjectWithIntrinsicsJacobian: the pixel of Project, and its derivatives by the point and the "
    "18 intrinsics as autodiff's",
    "[camera]") {
  using Jet21 = ceres::Jet<double, 3 + OpenCVCameraModel::kNumParams>;
  using Jet16 = ceres::Jet<double, 2 + OpenCVCameraModel::kNumDistortion>;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> xy(-0.6, 0.6), depth(0.5, 3.0);
  for (const auto& dist : kDistortions) {
    const Camera camera = MakeCamera(dist);
    for (int i = 0; i < 20; ++i) {
      const double z = depth(rng);
      const double p[3] = {xy(rng) * z, xy(rng) * z, z};
      double uv[2];
      Eigen::Matrix<double, 2, 3> d_p;
      OpenCVCameraModel::IntrinsicsJacobian d_k;
      REQUIRE(OpenCVCameraModel::ProjectWithIntrinsicsJacobian<Jet16>(camera.params.data(), p, uv,
                                                                      &d_p, &d_k));
      // Reference: Project on jets over the point and every intrinsic.
      Jet21 p_jet[3], k_jet[OpenCVCameraModel::kNumParams], uv_jet[2];
      for (int j = 0; j < 3; ++j) p_jet[j] = Jet21(p[j], j);
      for (int j = 0; j < OpenCVCameraModel::kNumParams; ++j)
        k_jet[j] = Jet21(camera.params[j], 3 + j);
      REQUIRE(OpenCVCameraModel::Project(k_jet, p_jet, uv_jet));
      for (int r = 0; r < 2; ++r) {
        CHECK(uv[r] == Approx(uv_jet[r].a).epsilon(1e-14));
        for (int j = 0; j < 3; ++j)
          CHECK(d_p(r, j) == Approx(uv_jet[r].v[j]).epsilon(1e-10).margin(1e-9));
        for (int j = 0; j < OpenCVCameraModel::kNumParams; ++j)
          CHECK(d_k(r, j) == Approx(uv_jet[r].v[3 + j]).epsilon(1e-10).margin(1e-9));
      }
    }
  }
  const double behind[3] = {0.1, 0.1, -1.0};
  double uv[2];
  Eigen::Matrix<double, 2, 3> d_p;
  OpenCVCameraModel::IntrinsicsJacobian d_k;
  CHECK_FALSE(OpenCVCameraModel::ProjectWithIntrinsicsJacobian<Jet16>(MakeCamera({}).params.data(),
                                                                      behind, uv, &d_p, &d_k));
}
