// SPDX-License-Identifier: GPL-2.0-or-later
// When the checkerboard detector must say "not found", and that it can be
// shared between threads.
#include "handeye/detectors/checkerboard_detector.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <thread>

#include "board_views.h"
#include "handeye/detectors/registry.h"
#include "handeye/sim/render.h"
#include <opencv2/core.hpp>

using namespace handeye;

namespace {

const Camera& TestCamera() {
  static const Camera camera = test::MakeTestCamera(800, 600, 720.0, test::MildDistortion());
  return camera;
}

}  // namespace

TEST_CASE("Checkerboard detector: no board in a cluttered image gives nullopt", "[checkerboard]") {
  auto board = std::make_shared<const CheckerboardTarget>(7, 6, 0.03);
  const auto detector = MakeDetector(board);
  Eigen::Isometry3d behind_camera = Eigen::Isometry3d::Identity();
  behind_camera.translation() = Eigen::Vector3d(0, 0, -1);
  for (std::uint64_t seed : {1, 2, 3}) {
    RenderOptions options;
    options.seed = seed;
    const cv::Mat image = RenderView(TestCamera(), *board, behind_camera, options);
    CHECK_FALSE(detector->Detect(image));
  }
  CHECK_FALSE(detector->Detect(cv::Mat(600, 800, CV_8U, cv::Scalar(128))));
}

TEST_CASE("Checkerboard detector: a board partly outside the image gives nullopt",
          "[checkerboard]") {
  // A checkerboard has no per-corner identity: only the full grid of inner
  // corners can be numbered.
  auto board = std::make_shared<const CheckerboardTarget>(7, 6, 0.03);
  const auto detector = MakeDetector(board);
  const Camera& camera = TestCamera();
  const std::pair<double, double> offsets[] = {{0.5, 0.0}, {-0.5, 0.1}, {0.0, 0.36}};
  std::uint64_t seed = 0;
  for (const auto& [x, y] : offsets) {
    const Eigen::Isometry3d T_cam_target = test::BoardPose(*board, 0.75, 0.2, 0.2, {1, 0}, {x, y});
    int inside = 0;
    for (const auto& uv : test::TruePixels(camera, *board, T_cam_target))
      inside += camera.InImage(uv);
    INFO("corners inside the image: " << inside << " of 42");
    REQUIRE(inside >= 10);
    REQUIRE(inside < 42);
    RenderOptions options;
    options.seed = ++seed;
    CHECK_FALSE(detector->Detect(RenderView(camera, *board, T_cam_target, options)));
  }
}

TEST_CASE("Checkerboard detector rejects images that are not 8-bit grey", "[checkerboard]") {
  const CheckerboardDetector detector(std::make_shared<const CheckerboardTarget>(4, 3, 0.03));
  CHECK_THROWS_AS(detector.Detect(cv::Mat()), std::invalid_argument);
  CHECK_THROWS_AS(detector.Detect(cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(0))),
                  std::invalid_argument);
  CHECK_THROWS_AS(detector.Detect(cv::Mat(48, 64, CV_32F, cv::Scalar(0))), std::invalid_argument);
}

TEST_CASE("Checkerboard detector can be used from several threads at once", "[checkerboard]") {
  auto board = std::make_shared<const CheckerboardTarget>(6, 5, 0.03);
  const auto detector = MakeDetector(board);
  std::vector<cv::Mat> images;
  for (int k = 0; k < 4; ++k) {
    RenderOptions options;
    options.seed = 40 + k;
    images.push_back(RenderView(TestCamera(), *board,
                                test::BoardPose(*board, 0.8, 0.7 * k, 0.3, {1, k}, {0.05 * k, 0}),
                                options));
  }
  std::vector<std::optional<Detection>> sequential, parallel(images.size());
  for (const auto& image : images) sequential.push_back(detector->Detect(image));
  std::vector<std::thread> threads;
  for (size_t k = 0; k < images.size(); ++k)
    threads.emplace_back([&, k] { parallel[k] = detector->Detect(images[k]); });
  for (auto& t : threads) t.join();
  for (size_t k = 0; k < images.size(); ++k) {
    REQUIRE(sequential[k]);
    REQUIRE(parallel[k]);
    CHECK(parallel[k]->ids == sequential[k]->ids);
    for (size_t i = 0; i < sequential[k]->points_px.size(); ++i)
      CHECK(parallel[k]->points_px[i] == sequential[k]->points_px[i]);
  }
}

TEST_CASE("Checkerboard detector gives the same corners whatever OpenCV's random state",
          "[checkerboard]") {
  // The sector detector draws from the calling thread's cv::theRNG(), whose
  // state depends on what that thread did before: with several detection
  // threads, which worker took which image changed the corners of oblique
  // views by up to 0.005 px between two runs on the same dataset.
  auto board = std::make_shared<const CheckerboardTarget>(4, 3, 0.05);
  const auto detector = MakeDetector(board);
  int compared = 0;
  for (int k = 0; k < 12; ++k) {
    RenderOptions options;
    options.seed = 70 + k;
    const double tilt = (50 + 2 * k) * M_PI / 180;
    const cv::Mat image = RenderView(
        TestCamera(), *board,
        test::BoardPose(*board, 1.6, 0.5 * k, tilt, {std::cos(k), std::sin(k)}, {0.1, -0.05}),
        options);
    std::optional<Detection> first, second;
    cv::theRNG().state = 1;
    first = detector->Detect(image);
    CHECK(cv::theRNG().state == 1);  // the caller's random state is left as it was
    cv::theRNG().state = 0x123456789abcdefULL;
    second = detector->Detect(image);
    REQUIRE(first.has_value() == second.has_value());
    if (!first) continue;
    ++compared;
    CHECK(first->ids == second->ids);
    for (size_t i = 0; i < first->points_px.size(); ++i)
      CHECK(first->points_px[i] == second->points_px[i]);
  }
  CHECK(compared >= 8);
}
