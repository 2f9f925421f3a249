// SPDX-License-Identifier: GPL-2.0-or-later
// Corner accuracy against the renderer's ground truth (Camera::Project of the
// target corners), over the image sizes, square sizes and blur a workcell
// camera sees. The bounds are requirements, not measurements: 0.05 px mean for
// squares of 30 px and more, 0.15 px for 10 px squares.
#include <catch2/catch.hpp>
#include <memory>
#include <random>
#include <sstream>

#include "board_views.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/render.h"

using namespace handeye;

namespace {

struct AccuracyCase {
  int width, height;
  double square_px;  ///< square size in the image (fronto-parallel, at the board's centre)
  double blur_sigma_px;
  int cols, rows;  ///< inner corners, cols + rows odd
  double bound_mean_px;
};

struct AccuracyResult {
  int views = 0, found = 0, corners = 0;
  double mean_px = 0, max_px = 0;
};

AccuracyResult MeasureAccuracy(const AccuracyCase& c, int num_views, std::uint64_t seed) {
  const double f = 0.9 * c.width;
  const Camera camera = test::MakeTestCamera(c.width, c.height, f, test::MildDistortion());
  const double square_m = 0.03;
  auto board = std::make_shared<const CheckerboardTarget>(c.cols, c.rows, square_m);
  const auto detector = MakeDetector(board);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  AccuracyResult result;
  double sum = 0;
  while (result.views < num_views) {
    // Random in-plane turn, a tilt of up to 20°, anywhere in the image with
    // the whole sheet inside it.
    const double distance = f * square_m / c.square_px;
    const Eigen::Isometry3d T_cam_target = test::BoardPose(
        *board, distance, M_PI * unit(rng), 0.35 * std::abs(unit(rng)), {unit(rng), unit(rng)},
        {0.3 * unit(rng) * c.width / f, 0.3 * unit(rng) * c.height / f});
    if (!test::SheetInImage(camera, *board, T_cam_target, 5.0)) continue;
    RenderOptions options;
    options.blur_sigma_px = c.blur_sigma_px;
    options.noise_sigma = 2.0;
    options.seed = rng();
    const cv::Mat image = RenderView(camera, *board, T_cam_target, options);
    ++result.views;
    const auto detection = detector->Detect(image);
    if (!detection) continue;
    ++result.found;
    const auto truth = test::TruePixels(camera, *board, T_cam_target);
    for (size_t k = 0; k < detection->ids.size(); ++k) {
      const double error = (detection->points_px[k] - truth[detection->ids[k]]).norm();
      sum += error;
      result.max_px = std::max(result.max_px, error);
      ++result.corners;
    }
  }
  result.mean_px = result.corners ? sum / result.corners : INFINITY;
  return result;
}

void CheckAccuracy(const AccuracyCase& c, std::uint64_t seed) {
  constexpr int kViews = 10;
  const AccuracyResult r = MeasureAccuracy(c, kViews, seed);
  std::ostringstream figure;
  figure << c.width << "x" << c.height << ", " << c.square_px << " px squares, blur "
         << c.blur_sigma_px << " px, noise 2: found " << r.found << "/" << r.views
         << ", corner error mean " << r.mean_px << " px, max " << r.max_px << " px (bound "
         << c.bound_mean_px << ")";
  WARN(figure.str());
  CHECK(r.found == r.views);
  CHECK(r.mean_px <= c.bound_mean_px);
}

}  // namespace

TEST_CASE("Checkerboard accuracy: 10 px squares, 1280x720, blur 0.5", "[checkerboard][accuracy]") {
  CheckAccuracy({1280, 720, 10, 0.5, 12, 9, 0.15}, 101);
}

TEST_CASE("Checkerboard accuracy: 10 px squares, 1920x1080, blur 1.0", "[checkerboard][accuracy]") {
  CheckAccuracy({1920, 1080, 10, 1.0, 12, 9, 0.15}, 102);
}

TEST_CASE("Checkerboard accuracy: 30 px squares, 1280x720, blur 0.7", "[checkerboard][accuracy]") {
  CheckAccuracy({1280, 720, 30, 0.7, 9, 6, 0.05}, 103);
}

TEST_CASE("Checkerboard accuracy: 30 px squares, 1920x1080, blur 1.0", "[checkerboard][accuracy]") {
  CheckAccuracy({1920, 1080, 30, 1.0, 9, 6, 0.05}, 104);
}

TEST_CASE("Checkerboard accuracy: 60 px squares, 1920x1080, blur 0.5", "[checkerboard][accuracy]") {
  CheckAccuracy({1920, 1080, 60, 0.5, 9, 6, 0.05}, 105);
}
