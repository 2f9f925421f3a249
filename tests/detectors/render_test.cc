// SPDX-License-Identifier: GPL-2.0-or-later
// The renderer is the ground truth of every detector accuracy figure, so its
// own conventions and bias are pinned here first.
#include "handeye/sim/render.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "board_views.h"

using namespace handeye;
using handeye::test::MakeTestCamera;
using handeye::test::MildDistortion;

namespace {

RenderOptions CleanOptions() {
  RenderOptions options;
  options.clutter = false;
  options.noise_sigma = 0.0;
  options.blur_sigma_px = 0.8;
  return options;
}

int Pixel(const cv::Mat& image, int u, int v) { return image.at<std::uint8_t>(v, u); }

/// Sub-pixel position where the edge between two flat levels crosses image
/// row v, from the pixel sum over [u_lo, u_hi]: with area sampling the sum of
/// the normalised levels is the length of the bright part of the row, and
/// blur (a convolution) keeps that sum when the window spans its kernel.
double EdgeCrossingInRow(const cv::Mat& image, int v, int u_lo, int u_hi, double black,
                         double white) {
  double bright = 0;
  for (int u = u_lo; u <= u_hi; ++u) bright += (Pixel(image, u, v) - black) / (white - black);
  const bool bright_on_right = Pixel(image, u_hi, v) > Pixel(image, u_lo, v);
  return bright_on_right ? (u_hi + 0.5) - bright : (u_lo - 0.5) + bright;
}

}  // namespace

TEST_CASE("RenderOptions::Check rejects bad values", "[render]") {
  std::string why;
  RenderOptions options;
  CHECK(options.Check(&why));
  options.supersampling = 0;
  CHECK_FALSE(options.Check(&why));
  CHECK(why.find("supersampling") != std::string::npos);
  options = RenderOptions();
  options.black_level = 200;
  options.white_level = 100;
  CHECK_FALSE(options.Check(&why));
  options = RenderOptions();
  options.background_level = 256;
  CHECK_FALSE(options.Check(&why));
  CHECK(why.find("background_level") != std::string::npos);
  options = RenderOptions();
  options.noise_sigma = -1;
  CHECK_FALSE(options.Check(&why));
  CHECK_THROWS_AS(RenderView(MakeTestCamera(64, 48, 50, {}), CheckerboardTarget(3, 2, 0.01),
                             Eigen::Isometry3d::Identity(), options),
                  std::invalid_argument);
}

TEST_CASE("Render pixel convention: a corner at an integer pixel is point-symmetric about it",
          "[render]") {
  // SPEC §2: the centre of the top-left pixel is (0, 0). A board corner placed
  // exactly on pixel (u0, v0) must give an image point-symmetric about that
  // pixel's centre; with the (0.5, 0.5) convention it would be symmetric about
  // (u0 - 0.5, v0 - 0.5) instead.
  const Camera camera = MakeTestCamera(160, 120, 200.0, {});
  const CheckerboardTarget board(3, 3, 0.05);
  const int u0 = 77, v0 = 58;
  const double distance = 0.5;
  // Corner (1, 1) is at (s, s, 0); put it on the ray through (u0, v0).
  Eigen::Isometry3d T_cam_target = Eigen::Isometry3d::Identity();
  T_cam_target.translation() =
      Eigen::Vector3d((u0 - camera.cx()) / camera.fx() * distance - 0.05,
                      (v0 - camera.cy()) / camera.fy() * distance - 0.05, distance);
  REQUIRE((*camera.Project(T_cam_target * Eigen::Vector3d(0.05, 0.05, 0)) - Eigen::Vector2d(u0, v0))
              .norm() < 1e-9);
  const RenderOptions options = CleanOptions();
  const cv::Mat image = RenderView(camera, board, T_cam_target, options);

  for (int dv = -6; dv <= 6; ++dv)
    for (int du = -6; du <= 6; ++du)
      REQUIRE(std::abs(Pixel(image, u0 + du, v0 + dv) - Pixel(image, u0 - du, v0 - dv)) <= 1);
  // Square (1, 1) of the target lies at u > u0, v > v0 and is black (a + b even).
  CHECK(Pixel(image, u0 + 4, v0 + 4) == Approx(options.black_level).margin(1));
  CHECK(Pixel(image, u0 - 4, v0 + 4) == Approx(options.white_level).margin(1));
  // The edge runs through the centres of column u0: those pixels are half covered.
  const double mid = (options.black_level + options.white_level) / 2;
  CHECK(Pixel(image, u0, v0 + 5) == Approx(mid).margin(1));
  CHECK(Pixel(image, u0 + 5, v0) == Approx(mid).margin(1));
}

TEST_CASE("Render draws the pattern on the printed face only, or through a glass sheet",
          "[render]") {
  const Camera camera = MakeTestCamera(200, 150, 220.0, MildDistortion());
  const CheckerboardTarget board(4, 3, 0.04);
  RenderOptions options;  // clutter and noise on: the images must still match exactly
  options.seed = 11;
  const Eigen::Isometry3d front = test::BoardPose(board, 0.9, 0.2, 0.3, {1, 0}, {0, 0});
  // The same sheet turned over about its own centre line: seen from behind.
  const Eigen::Vector3d centre(0.06, 0.04, 0.0);
  const Eigen::Isometry3d behind = front * Eigen::Translation3d(centre) *
                                   Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()) *
                                   Eigen::Translation3d(-centre);
  REQUIRE((behind.inverse()).translation().z() > 0);  // camera on the back side
  // The board entirely behind the camera: nothing of it can be drawn.
  Eigen::Isometry3d behind_camera = front;
  behind_camera.translation().z() -= 2.0;

  const cv::Mat background = RenderView(camera, board, behind_camera, options);
  const cv::Mat back_view = RenderView(camera, board, behind, options);
  const cv::Mat front_view = RenderView(camera, board, front, options);
  RenderOptions glass = options;
  glass.see_through = true;
  const cv::Mat glass_back_view = RenderView(camera, board, behind, glass);
  // Where each view shows the sheet (away from its blurred edges), the grey
  // levels it has there: the printed face has black and white squares, the
  // back of a printed sheet is plain, a glass sheet shows the pattern.
  auto sheet_levels = [&](const cv::Mat& view) {
    cv::Mat differs;
    cv::compare(view, background, differs, cv::CMP_NE);
    cv::erode(differs, differs, cv::Mat::ones(7, 7, CV_8U));
    cv::Scalar mean, stddev;
    cv::meanStdDev(view, mean, stddev, differs);
    return std::make_pair(cv::countNonZero(differs), stddev[0]);
  };
  const auto [front_area, front_spread] = sheet_levels(front_view);
  const auto [back_area, back_spread] = sheet_levels(back_view);
  const auto [glass_area, glass_spread] = sheet_levels(glass_back_view);
  CHECK(front_area > 2000);
  CHECK(front_spread > 60);  // black and white squares
  CHECK(back_area > 2000);
  CHECK(back_spread < 5);  // plain: sensor noise only
  CHECK(glass_area > 2000);
  CHECK(glass_spread > 60);
}

TEST_CASE("Render is deterministic from the seed", "[render]") {
  const Camera camera = MakeTestCamera(240, 180, 250.0, MildDistortion());
  const CheckerboardTarget board(5, 4, 0.03);
  const Eigen::Isometry3d T = test::BoardPose(board, 0.8, 0.3, 0.2, {1, 1}, {0.02, -0.03});
  RenderOptions options;
  options.seed = 5;
  const cv::Mat a = RenderView(camera, board, T, options);
  const cv::Mat b = RenderView(camera, board, T, options);
  CHECK(cv::norm(a, b, cv::NORM_INF) == 0);
  options.seed = 6;
  const cv::Mat c = RenderView(camera, board, T, options);
  CHECK(cv::norm(a, c, cv::NORM_INF) > 0);
}

TEST_CASE("Render places edges where Camera::Project says, without bias", "[render]") {
  // Large squares, tilted, turned a little and through lens distortion. For
  // every image row that crosses a near-vertical board edge (and every column
  // crossing a near-horizontal one), the edge position measured from the
  // pixel sum must match the projection of the target-plane edge.
  const Camera camera = MakeTestCamera(640, 480, 600.0, MildDistortion());
  const CheckerboardTarget board(5, 4, 0.06);
  const double s = board.square_size_m();
  const Eigen::Isometry3d T_cam_target =
      test::BoardPose(board, 1.0, 0.12, 0.35, {1, 0.4}, {-0.02, 0.03});
  const RenderOptions options = CleanOptions();
  const cv::Mat image = RenderView(camera, board, T_cam_target, options);

  // Point of the target edge {x = x_m} (or {y = y_m}) whose image has the given
  // v (or u), by bisection along the edge; returns the other image coordinate.
  auto project = [&](double x, double y) {
    return *camera.Project(T_cam_target * Eigen::Vector3d(x, y, 0));
  };
  auto crossing = [&](bool vertical_edge, double line_m, double lo_m, double hi_m, double target) {
    auto at = [&](double t) { return vertical_edge ? project(line_m, t) : project(t, line_m); };
    const int coord = vertical_edge ? 1 : 0;
    const bool increasing = at(hi_m)[coord] > at(lo_m)[coord];
    for (int it = 0; it < 100; ++it) {
      const double mid = 0.5 * (lo_m + hi_m);
      if ((at(mid)[coord] < target) == increasing)
        lo_m = mid;
      else
        hi_m = mid;
    }
    return at(0.5 * (lo_m + hi_m))[1 - coord];
  };

  // Inner edges between squares of different colour: x = a·s for a in 0..cols-1
  // separate squares (a-1, b) and (a, b); measure on the middle of square b.
  double sum = 0, sum_abs = 0, worst = 0;
  int count = 0;
  for (int vertical = 0; vertical < 2; ++vertical) {
    for (int line = 0; line < (vertical ? board.cols() : board.rows()); ++line) {
      for (int cell = 0; cell + 1 < (vertical ? board.rows() : board.cols()); ++cell) {
        const double line_m = line * s, lo = (cell + 0.2) * s, hi = (cell + 0.8) * s;
        const Eigen::Vector2d a = vertical ? project(line_m, lo) : project(lo, line_m);
        const Eigen::Vector2d b = vertical ? project(line_m, hi) : project(hi, line_m);
        const int c0 = static_cast<int>(std::ceil(std::min(a[vertical], b[vertical])));
        const int c1 = static_cast<int>(std::floor(std::max(a[vertical], b[vertical])));
        for (int c = c0; c <= c1; ++c) {
          const double truth = crossing(vertical, line_m, lo, hi, c);
          const int centre = static_cast<int>(std::lround(truth));
          double measured;
          if (vertical) {
            measured = EdgeCrossingInRow(image, c, centre - 8, centre + 8, options.black_level,
                                         options.white_level);
          } else {
            cv::Mat column = image.col(c).t();
            measured = EdgeCrossingInRow(column, 0, centre - 8, centre + 8, options.black_level,
                                         options.white_level);
          }
          const double error = measured - truth;
          sum += error;
          sum_abs += std::abs(error);
          worst = std::max(worst, std::abs(error));
          ++count;
        }
      }
    }
  }
  const int n = options.supersampling;
  WARN("render edge crossings: " << count << ", signed mean " << sum / count << " px, mean |error| "
                                 << sum_abs / count << " px, worst " << worst << " px (n = " << n
                                 << ")");
  REQUIRE(count > 500);
  // No bias: the signed errors average out.
  CHECK(std::abs(sum / count) < 0.003);
  // Per crossing, n × n samples resolve a pixel's coverage to about 1/(2n) in
  // the pattern's worst edge direction (to 1/(2n²) for edges along the pixel
  // grid), plus 8-bit rounding of the few pixels on the edge.
  CHECK(worst < 1.0 / (2 * n) + 0.01);
  CHECK(sum_abs / count < 0.25 / n);
}

TEST_CASE("Render places an edge along the pixel grid to 1/(2n²) px", "[render]") {
  // A fronto-parallel board: vertical and horizontal edges at known
  // fractional positions, where the sampling pattern (n² distinct columns and
  // rows) is at its most precise.
  const Camera camera = MakeTestCamera(200, 160, 250.0, {});
  const CheckerboardTarget board(3, 3, 0.04);
  const RenderOptions options = CleanOptions();
  const int n = options.supersampling;
  for (double frac : {0.0, 0.13, 0.29, 0.5, 0.71, 0.9}) {
    const double u_edge = 101 + frac, v_edge = 77 - frac;  // corner (1, 1)
    const double distance = 0.6;
    Eigen::Isometry3d T_cam_target = Eigen::Isometry3d::Identity();
    T_cam_target.translation() =
        Eigen::Vector3d((u_edge - camera.cx()) / camera.fx() * distance - 0.04,
                        (v_edge - camera.cy()) / camera.fy() * distance - 0.04, distance);
    const cv::Mat image = RenderView(camera, board, T_cam_target, options);
    for (int k = 4; k <= 12; k += 4) {
      // Rows below and columns left of corner (1, 1) cross single edges.
      const double u = EdgeCrossingInRow(image, static_cast<int>(v_edge) + k, 93, 109,
                                         options.black_level, options.white_level);
      const cv::Mat column = image.col(static_cast<int>(u_edge) - k).t();
      const double v =
          EdgeCrossingInRow(column, 0, 69, 85, options.black_level, options.white_level);
      INFO("edge at u = " << u_edge << ", v = " << v_edge << "; measured " << u << ", " << v);
      CHECK(std::abs(u - u_edge) < 1.0 / (2 * n * n) + 0.005);
      CHECK(std::abs(v - v_edge) < 1.0 / (2 * n * n) + 0.005);
    }
  }
}
