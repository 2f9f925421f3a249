// SPDX-License-Identifier: GPL-2.0-or-later
// The saddle-point clusters that tell the checkerboard detector where to
// search crops: every inner corner of a rendered board falls in one of the
// largest clusters, at the square sizes and blur the detector must handle.
#include "../../detectors/src/saddle_regions.h"

#include <catch2/catch.hpp>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "board_views.h"
#include "handeye/sim/render.h"

using namespace handeye;

namespace {

// Index of the first region holding every point, or -1.
int RegionHolding(const std::vector<internal::SaddleRegion>& regions,
                  const std::vector<cv::Point2d>& points) {
  for (std::size_t k = 0; k < regions.size(); ++k) {
    bool all = true;
    for (const auto& p : points) {
      const cv::Rect& b = regions[k].box;
      all =
          all && p.x >= b.x - 1 && p.y >= b.y - 1 && p.x <= b.x + b.width && p.y <= b.y + b.height;
    }
    if (all) return static_cast<int>(k);
  }
  return -1;
}

}  // namespace

TEST_CASE("Saddle regions hold the inner corners of rendered boards", "[checkerboard]") {
  struct SaddleCase {
    int width, height;
    double square_px, blur_px, tilt_rad;
  };
  // Squares of 10 px (5 px in the half-resolution image searched) to 40 px,
  // head-on and seen at 60°.
  const SaddleCase cases[] = {
      {1920, 1080, 10, 1.0, 0.2}, {1280, 720, 30, 0.7, 0.3}, {1920, 1080, 40, 1.0, 1.05}};
  std::uint64_t seed = 7;
  for (const SaddleCase& c : cases) {
    const double f = 0.9 * c.width;
    const Camera camera = test::MakeTestCamera(c.width, c.height, f, test::MildDistortion());
    auto board = std::make_shared<const CheckerboardTarget>(7, 6, 0.03);
    const Eigen::Isometry3d T_cam_target =
        test::BoardPose(*board, f * 0.03 / c.square_px, 0.4, c.tilt_rad, {1, 1}, {0.1, -0.05});
    REQUIRE(test::SheetInImage(camera, *board, T_cam_target, 5.0));
    RenderOptions options;
    options.blur_sigma_px = c.blur_px;
    options.noise_sigma = 2.0;
    options.seed = ++seed;
    const cv::Mat image = RenderView(camera, *board, T_cam_target, options);
    cv::Mat half;
    cv::resize(image, half, cv::Size(c.width / 2, c.height / 2), 0, 0, cv::INTER_AREA);
    const auto regions = internal::SaddleRegions(half, internal::SaddleRegionOptions{});
    // Half pixel k has its centre at full pixel 2k + 0.5.
    std::vector<cv::Point2d> corners;
    for (const auto& uv : test::TruePixels(camera, *board, T_cam_target))
      corners.emplace_back((uv.x() - 0.5) / 2, (uv.y() - 0.5) / 2);
    INFO(c.width << "x" << c.height << ", " << c.square_px << " px squares, tilt " << c.tilt_rad
                 << " rad: " << regions.size() << " regions");
    const int k = RegionHolding(regions, corners);
    CHECK(k >= 0);
    CHECK(k < 3);
  }
}

TEST_CASE("Saddle regions: none in a flat or a smoothly shaded image", "[checkerboard]") {
  const internal::SaddleRegionOptions options;
  CHECK(internal::SaddleRegions(cv::Mat(300, 400, CV_8U, cv::Scalar(90)), options).empty());
  cv::Mat ramp(300, 400, CV_8U);
  for (int y = 0; y < ramp.rows; ++y)
    for (int x = 0; x < ramp.cols; ++x)
      ramp.at<std::uint8_t>(y, x) =
          static_cast<std::uint8_t>(x * y / 500);  // a saddle, but a weak one
  CHECK(internal::SaddleRegions(ramp, options).empty());
  CHECK(internal::SaddleRegions(cv::Mat(3, 3, CV_8U, cv::Scalar(0)), options).empty());
}
