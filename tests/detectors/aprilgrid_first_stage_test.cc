// SPDX-License-Identifier: GPL-2.0-or-later
// The AprilGrid detector's first stage: the library's second pass runs only
// when its first finds a tag of the grid. Views of the grid must come out
// exactly as with both passes always; images without the grid (rendered
// clutter) must give nothing.
#include <catch2/catch.hpp>
#include <random>

#include "handeye/detectors/aprilgrid_detector.h"
#include "handeye/sim/render.h"
#include "rendered_views.h"

using namespace handeye;

namespace {

std::shared_ptr<const AprilGridTarget> FirstStageGrid() {
  TargetSpec spec;
  spec.type = "aprilgrid";
  spec.values["tags"] = std::vector<double>{6.0, 4.0};
  spec.values["tag_size_m"] = 0.05;
  spec.values["tag_spacing"] = 0.25;
  return MakeAprilGridTarget(spec);
}

}  // namespace

TEST_CASE("aprilgrid first stage: the same detections, small and oblique tags included",
          "[aprilgrid][cascade]") {
  const auto grid = FirstStageGrid();
  AprilGridDetector::Options without;
  without.first_stage = false;
  const AprilGridDetector fast(grid), full(grid, without);
  const Camera camera = test::PinholeCamera(1920, 1080, 0.714 * 1920);
  test::ViewSampling sampling;
  sampling.feature_m = 0.05;
  // Down to the smallest tags the detector keeps (15 px), up to 60° of tilt.
  sampling.min_feature_px = 15;
  sampling.max_feature_px = 50;
  sampling.max_tilt_deg = 60;
  sampling.centre_beyond_border = 0.0;
  std::mt19937_64 rng(12);
  int detected = 0;
  for (int view = 0; view < 24; ++view) {
    INFO("view " << view);
    RenderOptions options;
    options.seed = 100 + view;
    options.blur_sigma_px = view % 3 == 0 ? 1.5 : 0.7;
    const cv::Mat image =
        RenderView(camera, *grid, test::RandomView(camera, *grid, sampling, &rng), options);
    const auto a = fast.Detect(image), b = full.Detect(image);
    REQUIRE(a.has_value() == b.has_value());
    if (!a) continue;
    ++detected;
    CHECK(a->ids == b->ids);
    CHECK(a->points_px == b->points_px);
  }
  CAPTURE(detected);
  CHECK(detected >= 12);
}

TEST_CASE("aprilgrid first stage: rendered clutter without the grid gives nothing",
          "[aprilgrid][cascade]") {
  const auto grid = FirstStageGrid();
  const AprilGridDetector detector(grid);
  const Camera camera = test::PinholeCamera(1920, 1080, 0.714 * 1920);
  // The grid behind the camera: only the renderer's clutter is in view.
  Eigen::Isometry3d behind_camera = Eigen::Isometry3d::Identity();
  behind_camera.translation() = Eigen::Vector3d(0, 0, -1);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    RenderOptions options;
    options.seed = seed;
    const cv::Mat image = RenderView(camera, *grid, behind_camera, options);
    CHECK(detector.DetectRawTags(image).empty());
    CHECK_FALSE(detector.Detect(image));
  }
}
