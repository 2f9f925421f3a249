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
#include "handeye/sim/render.h"

using namespace handeye;

namespace {

struct AccuracyCase {
  int width, height;
  double square_px;  ///< square size in the image (fronto-parallel, at the board's centre)
  double blur_sigma_px;
  int cols, rows;  ///< inner corners, cols + rows odd
  double bound_mean_px;
  /// Tilt of the board away from facing the camera, drawn uniformly (rad).
  double tilt_min_rad = 0.0, tilt_max_rad = 0.35;
  /// Bound on the largest corner error of all views (px).
  double bound_max_px = INFINITY;
  /// Views in which the board must be found.
  double min_found_fraction = 1.0;
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
    // Random in-plane turn, a tilt in the case's range (up to 20° unless it
    // says otherwise), anywhere in the image with the whole sheet inside it.
    const double distance = f * square_m / c.square_px;
    // (The tilt is drawn inside the argument list, where the draws of the
    // cases without a tilt range were made, so that they keep their views.)
    const Eigen::Isometry3d T_cam_target = test::BoardPose(
        *board, distance, M_PI * unit(rng),
        c.tilt_min_rad + (c.tilt_max_rad - c.tilt_min_rad) * std::abs(unit(rng)),
        {unit(rng), unit(rng)}, {0.3 * unit(rng) * c.width / f, 0.3 * unit(rng) * c.height / f});
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

void CheckAccuracy(const AccuracyCase& c, std::uint64_t seed, int num_views = 10) {
  const AccuracyResult r = MeasureAccuracy(c, num_views, seed);
  std::ostringstream figure;
  figure << c.width << "x" << c.height << ", " << c.square_px << " px squares, blur "
         << c.blur_sigma_px << " px, noise 2: found " << r.found << "/" << r.views
         << ", corner error mean " << r.mean_px << " px, max " << r.max_px << " px (bound "
         << c.bound_mean_px << ")";
  WARN(figure.str());
  CHECK(r.found >= c.min_found_fraction * r.views);
  CHECK(r.mean_px <= c.bound_mean_px);
  CHECK(r.max_px <= c.bound_max_px);
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

// Seen obliquely (METRIC's synthetic cell has many such views of its 4x3
// board), the squares are sheared into rhombi: the grid lines parallel to a
// corner's own pass much closer to it than its neighbouring corners do, and a
// refinement window sized by the distance to the nearest corner took them in
// (errors up to 0.4 px with this seed, 2 px with others). The sector detector
// itself misses a few boards this oblique (2-5 of 20; it does not always
// return the same grid for the same image), hence the found fraction.
TEST_CASE("Checkerboard accuracy: 35 px squares seen at 55-65 degrees, 1920x1080, blur 1.0",
          "[checkerboard][accuracy]") {
  AccuracyCase c{1920, 1080, 35, 1.0, 4, 3, 0.05};
  c.tilt_min_rad = 55 * M_PI / 180;
  c.tilt_max_rad = 65 * M_PI / 180;
  c.bound_max_px = 0.3;
  c.min_found_fraction = 0.6;
  CheckAccuracy(c, 108, 20);
}
