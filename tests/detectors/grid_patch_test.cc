// SPDX-License-Identifier: GPL-2.0-or-later
// The checkerboard detector's first, cheap stage: a patch of corner grid
// among the saddle points of the half-resolution image. It must hold for
// every board the detector can find (small, blurred, seen obliquely), or
// those boards are lost; and it should not hold in images without a board
// (clutter, a board seen edge-on or from behind), where it saves OpenCV's
// whole-image searches.
#include "../../detectors/src/grid_patch.h"

#include <catch2/catch.hpp>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "board_views.h"
#include "handeye/detectors/registry.h"
#include "handeye/sim/render.h"

using namespace handeye;

namespace {

/// HasGridPatch on the image as the detector sees it: halved by averaging.
bool PatchInImage(const cv::Mat& image, int rows) {
  cv::Mat half;
  cv::resize(image(cv::Rect(0, 0, image.cols / 2 * 2, image.rows / 2 * 2)), half,
             cv::Size(image.cols / 2, image.rows / 2), 0, 0, cv::INTER_AREA);
  internal::GridPatchOptions options;
  options.rows = rows;
  return internal::HasGridPatch(
      internal::FindSaddlePoints(half, internal::SaddleRegionOptions{}), options);
}

}  // namespace

TEST_CASE("Grid patch: found on hard views of boards, which the detector still finds",
          "[checkerboard][cascade]") {
  struct Case {
    const char* what;
    int cols, rows;
    double square_px, blur_px, noise, tilt_rad, in_plane_rad;
  };
  const Case cases[] = {
      {"small squares", 7, 6, 10, 0.7, 2, 0.2, 0.3},
      {"blurred and noisy", 7, 6, 30, 2.0, 8, 0.3, 0.5},
      {"seen at 60 degrees", 7, 6, 40, 1.0, 2, 1.05, 0.4},
      {"METRIC's 4 x 3 board, small and oblique", 4, 3, 16, 1.0, 4, 0.9, 0.7},
      {"METRIC's 4 x 3 board, blurred", 4, 3, 30, 1.8, 6, 0.4, 1.2},
  };
  const int width = 1920, height = 1080;
  const double f = 0.9 * width;
  const Camera camera = test::MakeTestCamera(width, height, f, test::MildDistortion());
  std::uint64_t seed = 40;
  for (const Case& c : cases) {
    INFO(c.what);
    auto board = std::make_shared<const CheckerboardTarget>(c.cols, c.rows, 0.03);
    const Eigen::Isometry3d T_cam_target = test::BoardPose(
        *board, f * 0.03 / c.square_px, c.in_plane_rad, c.tilt_rad, {1, 1}, {0.15, -0.1});
    REQUIRE(test::SheetInImage(camera, *board, T_cam_target, 5.0));
    RenderOptions options;
    options.blur_sigma_px = c.blur_px;
    options.noise_sigma = c.noise;
    options.seed = ++seed;
    const cv::Mat image = RenderView(camera, *board, T_cam_target, options);
    CHECK(PatchInImage(image, std::min(c.rows, 3)));
    CHECK(MakeDetector(board)->Detect(image));
  }
}

TEST_CASE("Grid patch: none in clutter, nor with a board seen edge-on or from behind",
          "[checkerboard][cascade]") {
  const int width = 1920, height = 1080;
  const double f = 0.9 * width;
  const Camera camera = test::MakeTestCamera(width, height, f, test::MildDistortion());
  auto board = std::make_shared<const CheckerboardTarget>(7, 6, 0.03);
  const auto detector = MakeDetector(board);
  SECTION("rendered clutter without a board") {
    Eigen::Isometry3d behind_camera = Eigen::Isometry3d::Identity();
    behind_camera.translation() = Eigen::Vector3d(0, 0, -1);
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
      INFO("seed " << seed);
      RenderOptions options;
      options.seed = seed;
      const cv::Mat image = RenderView(camera, *board, behind_camera, options);
      CHECK_FALSE(PatchInImage(image, 3));
      CHECK_FALSE(detector->Detect(image));
    }
  }
  SECTION("a board edge-on, and turned away from the camera") {
    // 89.5° of tilt: the sheet is a sliver a few pixels wide; 180°: the
    // camera looks at its back, which the renderer draws blank.
    for (const double tilt_deg : {89.5, 180.0}) {
      INFO("tilt " << tilt_deg << " deg");
      const Eigen::Isometry3d T_cam_target =
          test::BoardPose(*board, 1.2, 0.3, tilt_deg * M_PI / 180, {1, 0}, {0.0, 0.0});
      RenderOptions options;
      options.seed = 21;
      const cv::Mat image = RenderView(camera, *board, T_cam_target, options);
      CHECK_FALSE(PatchInImage(image, 3));
      CHECK_FALSE(detector->Detect(image));
    }
  }
}
