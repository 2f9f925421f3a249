// SPDX-License-Identifier: GPL-2.0-or-later
// The checkerboard detector's crop path: the patches of corner grid that the
// first stage finds say where to search, and a board found in a crop around
// them must have the points a whole-image search gives it, whatever grid
// OpenCV's search returned there.
#include <catch2/catch.hpp>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <random>

#include "../../detectors/src/checkerboard_grid.h"
#include "../../detectors/src/grid_patch.h"
#include "board_views.h"
#include "handeye/detectors/registry.h"
#include "handeye/sim/render.h"

using namespace handeye;

namespace {

/// The half-resolution image the first stage looks at.
cv::Mat Half(const cv::Mat& image) { return internal::BlockMean(image, 2); }

struct CropView {
  std::shared_ptr<const CheckerboardTarget> board;
  cv::Mat image;
  std::vector<Eigen::Vector2d> truth;  // true pixel of every inner corner, by id
  /// True pixels of the corner grid continued one square past the inner
  /// corners: where the outer squares meet the sheet's margin.
  std::vector<Eigen::Vector2d> extended;
};

/// METRIC's 4 x 3 board, seen obliquely with 30 px squares.
CropView CropObliqueView(std::uint64_t seed, double blur_px = 0.75, double noise = 2.0) {
  const int width = 1920, height = 1080;
  const double f = 0.9 * width;
  const Camera camera = test::MakeTestCamera(width, height, f, test::MildDistortion());
  CropView view;
  view.board = std::make_shared<const CheckerboardTarget>(4, 3, 0.05);
  const Eigen::Isometry3d T_cam_target =
      test::BoardPose(*view.board, f * 0.05 / 30.0, 0.4, 0.8, {1, 1}, {0.2, -0.1});
  RenderOptions options;
  options.seed = seed;
  options.blur_sigma_px = blur_px;
  options.noise_sigma = noise;
  view.image = RenderView(camera, *view.board, T_cam_target, options);
  view.truth = test::TruePixels(camera, *view.board, T_cam_target);
  const double s = view.board->square_size_m();
  for (int j = -1; j <= view.board->rows(); ++j)
    for (int i = -1; i <= view.board->cols(); ++i)
      view.extended.push_back(*camera.Project(T_cam_target * Eigen::Vector3d(i * s, j * s, 0)));
  return view;
}

}  // namespace

TEST_CASE("Grid patches: on the board's corners, none in clutter", "[checkerboard][cascade]") {
  const CropView view = CropObliqueView(3);
  internal::GridPatchOptions options;
  const auto patches = internal::FindGridPatches(
      internal::FindSaddlePoints(Half(view.image), internal::SaddleRegionOptions{}), options);
  REQUIRE_FALSE(patches.empty());
  for (const auto& patch : patches) {
    REQUIRE(patch.corners.size() == 9);
    CHECK(patch.step_px > 5.0);
    // Every corner of a patch is one of the board's, or where its outer
    // squares meet the margin (half-resolution pixel k covers full pixels 2k
    // and 2k + 1, so its centre is at 2k + 0.5).
    for (const cv::Point& c : patch.corners) {
      double nearest = 1e9;
      for (const auto& t : view.extended)
        nearest = std::min(nearest, std::hypot(2 * c.x + 0.5 - t.x(), 2 * c.y + 0.5 - t.y()));
      CHECK(nearest < 3.0);
    }
  }
  // HasGridPatch is FindGridPatches with a limit of one.
  CHECK(
      internal::FindGridPatches(
          internal::FindSaddlePoints(Half(view.image), internal::SaddleRegionOptions{}), options, 1)
          .size() == 1);

  const Camera camera = test::MakeTestCamera(1920, 1080, 0.9 * 1920, test::MildDistortion());
  Eigen::Isometry3d behind_camera = Eigen::Isometry3d::Identity();
  behind_camera.translation() = Eigen::Vector3d(0, 0, -1);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    RenderOptions clutter;
    clutter.seed = seed;
    const cv::Mat image = RenderView(camera, *view.board, behind_camera, clutter);
    CHECK(internal::FindGridPatches(
              internal::FindSaddlePoints(Half(image), internal::SaddleRegionOptions{}), options)
              .empty());
  }
}

TEST_CASE("Saddle points: the local maxima of -det(H) that cv::Sobel's derivatives give",
          "[checkerboard][cascade]") {
  // The saddle search computes the Sobel derivatives, the strength and the
  // maxima itself, pixel by pixel; here the same from OpenCV's whole-image
  // operations, on a board among clutter and on clutter alone.
  const CropView view = CropObliqueView(5);
  const Camera camera = test::MakeTestCamera(1920, 1080, 0.9 * 1920, test::MildDistortion());
  Eigen::Isometry3d behind_camera = Eigen::Isometry3d::Identity();
  behind_camera.translation() = Eigen::Vector3d(0, 0, -1);
  RenderOptions clutter;
  clutter.seed = 2;
  for (const cv::Mat& image :
       {Half(view.image), Half(RenderView(camera, *view.board, behind_camera, clutter))}) {
    const internal::SaddleRegionOptions options;
    cv::Mat smooth;
    image.convertTo(smooth, CV_32F);
    cv::GaussianBlur(smooth, smooth, cv::Size(), options.sigma_px, options.sigma_px,
                     cv::BORDER_REPLICATE);
    cv::Mat dxx, dyy, dxy;
    cv::Sobel(smooth, dxx, CV_32F, 2, 0, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
    cv::Sobel(smooth, dyy, CV_32F, 0, 2, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
    cv::Sobel(smooth, dxy, CV_32F, 1, 1, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
    const cv::Mat strength = dxy.mul(dxy) - dxx.mul(dyy);
    const double ixy = 4.0 * options.min_contrast / (M_PI * options.sigma_px * options.sigma_px);
    cv::Mat dilated;
    cv::dilate(strength, dilated, cv::Mat());
    cv::Mat peaks = (strength >= dilated) & (strength > ixy * ixy);
    const cv::Rect inside(2, 2, peaks.cols - 4, peaks.rows - 4);
    std::vector<cv::Point> expected;
    cv::findNonZero(peaks(inside), expected);

    const auto saddles = internal::FindSaddlePoints(image, options);
    REQUIRE(saddles.size() == expected.size());
    CHECK(saddles.size() > 20);
    for (std::size_t i = 0; i < saddles.size(); ++i) {
      const cv::Point p = expected[i] + inside.tl();
      REQUIRE(saddles[i].pixel == p);
      const double scale = std::abs(dxx.at<float>(p)) + std::abs(dxy.at<float>(p)) +
                           std::abs(dyy.at<float>(p));
      CHECK(std::abs(saddles[i].dxx - dxx.at<float>(p)) <= 1e-5 * scale);
      CHECK(std::abs(saddles[i].dxy - dxy.at<float>(p)) <= 1e-5 * scale);
      CHECK(std::abs(saddles[i].dyy - dyy.at<float>(p)) <= 1e-5 * scale);
    }
  }
}

TEST_CASE("Grid refinement: the same points from whichever grid the search returned",
          "[checkerboard][cascade]") {
  // A crop and the whole image give OpenCV's search different grids to start
  // from (up to a pixel or so apart); the refined corners must not follow.
  const CropView view = CropObliqueView(5, 1.5, 8.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> shift(-1.5, 1.5);
  std::vector<std::vector<cv::Point2f>> results;
  for (int trial = 0; trial < 6; ++trial) {
    internal::Grid grid;
    grid.cols = view.board->cols();
    grid.rows = view.board->rows();
    for (const auto& t : view.truth)
      grid.px.emplace_back(static_cast<float>(t.x() + shift(rng)),
                           static_cast<float>(t.y() + shift(rng)));
    REQUIRE(internal::RefineGrid(view.image, &grid));
    results.push_back(grid.px);
  }
  double largest = 0, worst_error = 0;
  for (std::size_t k = 0; k < view.truth.size(); ++k) {
    for (const auto& r : results) {
      largest = std::max(largest, static_cast<double>(cv::norm(r[k] - results[0][k])));
      worst_error =
          std::max(worst_error, std::hypot(r[k].x - view.truth[k].x(), r[k].y - view.truth[k].y()));
    }
  }
  // One pass with windows sized from the starting grid differed by up to
  // 0.07 px on METRIC's oblique views.
  CAPTURE(largest, worst_error);
  CHECK(largest < 0.01);
  CHECK(worst_error < 0.2);
}

TEST_CASE("Checkerboard: a board found in a crop has the points the whole image gives",
          "[checkerboard][cascade]") {
  // The detector searches the crop around the patches first; the same board
  // pasted into a blank image of the crop's size is searched whole there.
  const CropView view = CropObliqueView(9);
  const auto found = MakeDetector(view.board)->Detect(view.image);
  REQUIRE(found);
  cv::Rect box = cv::boundingRect(std::vector<cv::Point2f>{cv::Point2f(
      static_cast<float>(view.truth.front().x()), static_cast<float>(view.truth.front().y()))});
  for (const auto& t : view.truth)
    box |= cv::Rect(static_cast<int>(t.x()), static_cast<int>(t.y()), 1, 1);
  // Far enough out for the outer squares and the white border; small enough
  // (under 480 px a side) that the detector searches it at full resolution.
  const int margin = 110;
  const cv::Rect crop =
      cv::Rect(box.x - margin, box.y - margin, box.width + 2 * margin, box.height + 2 * margin) &
      cv::Rect(0, 0, view.image.cols, view.image.rows);
  REQUIRE(std::min(crop.width, crop.height) < 480);
  const auto in_crop = MakeDetector(view.board)->Detect(view.image(crop).clone());
  REQUIRE(in_crop);
  REQUIRE(in_crop->ids == found->ids);
  double largest = 0;
  for (std::size_t k = 0; k < found->ids.size(); ++k)
    largest = std::max(
        largest,
        (in_crop->points_px[k] + Eigen::Vector2d(crop.x, crop.y) - found->points_px[k]).norm());
  CHECK(largest < 0.01);
}

TEST_CASE("Grid refinement: a grid shifted by one line is told from one that is no board's",
          "[checkerboard][cascade]") {
  // OpenCV's search sometimes returns a board's grid shifted by one line onto
  // the ends of its outer squares; the slower accurate search mends that, and
  // is run only where the grid less one outer line is a board's.
  const CropView view = CropObliqueView(11);
  const int cols = view.board->cols(), rows = view.board->rows();
  const int wide = cols + 2;  // view.extended runs from corner -1 to cols (rows)
  // The grid of cols x rows extended corners starting at corner (i0, j0).
  auto grid_from = [&](int i0, int j0) {
    internal::Grid grid;
    grid.cols = cols;
    grid.rows = rows;
    for (int j = j0; j < j0 + rows; ++j)
      for (int i = i0; i < i0 + cols; ++i) {
        const Eigen::Vector2d& p = view.extended[static_cast<std::size_t>(j + 1) * wide + (i + 1)];
        grid.px.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
      }
    return grid;
  };
  internal::Grid board = grid_from(0, 0);
  CHECK(internal::OneLineOff(view.image, board));
  REQUIRE(internal::RefineGrid(view.image, &board));
  for (const auto& [i0, j0] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
    CAPTURE(i0, j0);
    internal::Grid shifted = grid_from(i0, j0);
    CHECK(internal::OneLineOff(view.image, shifted));
    CHECK_FALSE(internal::RefineGrid(view.image, &shifted));
  }
  // Shifted across (one line each way) or by two lines, or corners of
  // clutter: nothing the accurate search would mend.
  CHECK_FALSE(internal::OneLineOff(view.image, grid_from(1, 1)));
  CHECK_FALSE(internal::OneLineOff(view.image, grid_from(-1, -1)));
  internal::Grid clutter;
  clutter.cols = cols;
  clutter.rows = rows;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> x(100, 1800), y(100, 1000);
  for (int k = 0; k < cols * rows; ++k) clutter.px.emplace_back(x(rng), y(rng));
  CHECK_FALSE(internal::OneLineOff(view.image, clutter));
}
