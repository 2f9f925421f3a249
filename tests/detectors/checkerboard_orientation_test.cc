// SPDX-License-Identifier: GPL-2.0-or-later
// Corner ids follow the board, not the image: SPEC §4's black-square rule and
// the handedness of the printed face decide them, however the board or the
// image is turned.
#include <catch2/catch.hpp>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>

#include "board_views.h"
#include "handeye/detectors/registry.h"
#include "handeye/sim/render.h"

using namespace handeye;
using handeye::test::BoardPose;
using handeye::test::MakeTestCamera;
using handeye::test::MildDistortion;
using handeye::test::TruePixels;

namespace {

/// Pixel (u, v) of an image of `size` after cv::rotate with `code`.
Eigen::Vector2d RotatedPixel(const Eigen::Vector2d& uv, const cv::Size& size, int code) {
  const double w = size.width, h = size.height;
  switch (code) {
    case cv::ROTATE_90_CLOCKWISE:
      return {h - 1 - uv.y(), uv.x()};
    case cv::ROTATE_180:
      return {w - 1 - uv.x(), h - 1 - uv.y()};
    case cv::ROTATE_90_COUNTERCLOCKWISE:
      return {uv.y(), w - 1 - uv.x()};
    default:
      return uv;
  }
}

/// The image and the true corner pixels, turned by 0, 90, 180 or 270 degrees.
struct OrientationView {
  cv::Mat image;
  std::vector<Eigen::Vector2d> truth;  ///< by id
};

std::vector<OrientationView> TurnedViews(const cv::Mat& image, const std::vector<Eigen::Vector2d>& truth) {
  std::vector<OrientationView> views{{image, truth}};
  for (int code : {cv::ROTATE_90_CLOCKWISE, cv::ROTATE_180, cv::ROTATE_90_COUNTERCLOCKWISE}) {
    OrientationView view;
    cv::rotate(image, view.image, code);
    for (const auto& uv : truth) view.truth.push_back(RotatedPixel(uv, image.size(), code));
    views.push_back(view);
  }
  return views;
}

/// Largest distance between each detected id and the true pixel of corner
/// `relabel(id)`; +inf when ids are missing or repeated.
double WorstError(const Detection& detection, const std::vector<Eigen::Vector2d>& truth,
                  const std::function<int(int)>& relabel) {
  if (detection.ids.size() != truth.size()) return INFINITY;
  std::vector<bool> seen(truth.size(), false);
  double worst = 0;
  for (size_t k = 0; k < detection.ids.size(); ++k) {
    const int id = detection.ids[k];
    if (id < 0 || id >= static_cast<int>(truth.size()) || seen[id]) return INFINITY;
    seen[id] = true;
    worst = std::max(worst, (detection.points_px[k] - truth[relabel(id)]).norm());
  }
  return worst;
}

/// Re-labellings that a board's symmetry leaves undecidable: identity, the
/// 180° turn when cols + rows is even, and the quarter turns of a board whose
/// four outer corner squares are all black (cols = rows, cols even). Mirror
/// images are never allowed: the printed face has a handedness.
std::vector<std::function<int(int)>> Symmetries(int cols, int rows) {
  std::vector<std::function<int(int)>> maps{[](int id) { return id; }};
  if ((cols + rows) % 2 == 0)
    maps.push_back([=](int id) { return (rows - 1 - id / cols) * cols + (cols - 1 - id % cols); });
  if (cols == rows && cols % 2 == 0) {
    const int n = cols;
    maps.push_back([=](int id) { return (id % n) * n + (n - 1 - id / n); });
    maps.push_back([=](int id) { return (n - 1 - id % n) * n + id / n; });
  }
  return maps;
}

const double kInPlaneDeg[] = {0.0, 35.0, 100.0, 180.0, 260.0};

void CheckIdsFollowTheBoard(int cols, int rows, const std::vector<double>& in_plane_degs,
                            int seed) {
  const Camera camera = MakeTestCamera(640, 480, 640.0, MildDistortion());
  auto board = std::make_shared<const CheckerboardTarget>(cols, rows, 0.04);
  REQUIRE(board->Warnings().empty());
  const auto detector = MakeDetector(board);
  for (double in_plane_deg : in_plane_degs) {
    // 180° in-plane: the board is seen upside down.
    const Eigen::Isometry3d T_cam_target =
        BoardPose(*board, 0.7, in_plane_deg * M_PI / 180, 0.3, {1, 0.5}, {0.02, -0.01});
    RenderOptions options;
    options.seed = ++seed;
    const cv::Mat image = RenderView(camera, *board, T_cam_target, options);
    const auto truth = TruePixels(camera, *board, T_cam_target);
    int turn = 0;
    for (const OrientationView& view : TurnedViews(image, truth)) {
      INFO(cols << " x " << rows << " board turned " << in_plane_deg
                << " deg in plane, image turned " << 90 * turn++ << " deg");
      const auto detection = detector->Detect(view.image);
      REQUIRE(detection);
      CHECK(WorstError(*detection, view.truth, [](int id) { return id; }) < 0.3);
    }
  }
}

}  // namespace

TEST_CASE("Checkerboard ids follow the board through image and board rotations", "[checkerboard]") {
  // cols + rows odd, so every id is decidable. 6 x 3: cols a multiple of rows,
  // where reading OpenCV's point list with the wrong row length looks
  // plausible row by row.
  CheckIdsFollowTheBoard(5, 4, {std::begin(kInPlaneDeg), std::end(kInPlaneDeg)}, 0);
  CheckIdsFollowTheBoard(6, 3, {10.0, 95.0}, 100);
}

TEST_CASE("Square checkerboard: quarter turns resolved, the 180-degree turn consistent",
          "[checkerboard]") {
  // 5 x 5: cols + rows even, so 180° cannot be told; but two of the four outer
  // corner squares are white, so 90° turns can.
  const Camera camera = MakeTestCamera(640, 480, 640.0, MildDistortion());
  auto board = std::make_shared<const CheckerboardTarget>(5, 5, 0.035);
  CHECK_FALSE(board->Warnings().empty());
  const auto detector = MakeDetector(board);
  const auto symmetries = Symmetries(5, 5);
  REQUIRE(symmetries.size() == 2);
  int seed = 10;
  for (double in_plane_deg : kInPlaneDeg) {
    const Eigen::Isometry3d T_cam_target =
        BoardPose(*board, 0.7, in_plane_deg * M_PI / 180, 0.25, {0.3, 1}, {-0.02, 0.01});
    RenderOptions options;
    options.seed = ++seed;
    const cv::Mat image = RenderView(camera, *board, T_cam_target, options);
    int turn = 0;
    for (const OrientationView& view : TurnedViews(image, TruePixels(camera, *board, T_cam_target))) {
      INFO("board turned " << in_plane_deg << " deg in plane, image turned " << 90 * turn++
                           << " deg");
      const auto detection = detector->Detect(view.image);
      REQUIRE(detection);
      double best = INFINITY;
      for (const auto& relabel : symmetries)
        best = std::min(best, WorstError(*detection, view.truth, relabel));
      CHECK(best < 0.3);
    }
  }
}

TEST_CASE("Ambiguous checkerboards warn and are numbered up to their symmetry", "[checkerboard]") {
  const Camera camera = MakeTestCamera(640, 480, 640.0, MildDistortion());
  const std::pair<int, int> sizes[] = {{4, 4}, {5, 3}, {6, 4}};
  int seed = 20;
  for (const auto& [cols, rows] : sizes) {
    INFO(cols << " x " << rows);
    auto board = std::make_shared<const CheckerboardTarget>(cols, rows, 0.04);
    CHECK(board->IsAmbiguous());
    CHECK_FALSE(board->Warnings().empty());
    const auto detector = MakeDetector(board);
    const auto symmetries = Symmetries(cols, rows);
    for (double in_plane_deg : {20.0, 200.0}) {
      const Eigen::Isometry3d T_cam_target =
          BoardPose(*board, 0.7, in_plane_deg * M_PI / 180, 0.3, {1, 1}, {0.0, 0.02});
      RenderOptions options;
      options.seed = ++seed;
      const cv::Mat image = RenderView(camera, *board, T_cam_target, options);
      const auto detection = detector->Detect(image);
      REQUIRE(detection);
      double best = INFINITY;
      for (const auto& relabel : symmetries)
        best = std::min(best,
                        WorstError(*detection, TruePixels(camera, *board, T_cam_target), relabel));
      CHECK(best < 0.3);
    }
  }
}

TEST_CASE("A board declared the wrong way round is named with the size to declare",
          "[checkerboard][transposed]") {
  // An 11 x 9 board declared [9, 11]: cols and rows both odd, so the declared
  // board's black outer corner squares are white in the images and no
  // numbering of the declared size fits. Turned boards and a second seed.
  const Camera camera = MakeTestCamera(640, 480, 640.0, MildDistortion());
  auto board = std::make_shared<const CheckerboardTarget>(11, 9, 0.025);
  const auto declared = MakeDetector(std::make_shared<const CheckerboardTarget>(9, 11, 0.025));
  const auto right = MakeDetector(board);
  int seed = 40;
  for (double in_plane_deg : {10.0, 100.0, 190.0}) {
    INFO("board turned " << in_plane_deg << " deg in plane");
    const Eigen::Isometry3d T_cam_target =
        BoardPose(*board, 0.6, in_plane_deg * M_PI / 180, 0.3, {1, 0.4}, {0.01, 0.0});
    RenderOptions options;
    options.seed = ++seed;
    const cv::Mat image = RenderView(camera, *board, T_cam_target, options);
    std::string mismatch = "stale";
    CHECK_FALSE(declared->DetectOrExplain(image, &mismatch));
    CHECK(mismatch ==
          "the board in the images has 11x9 inner corners; the target declares inner_corners "
          "[9, 11]: swap it to [11, 9]");
    // The board declared as it is printed: found, nothing to explain.
    const auto detection = right->DetectOrExplain(image, &mismatch);
    REQUIRE(detection);
    double best = INFINITY;  // cols + rows even: numbered up to the half turn
    for (const auto& relabel : Symmetries(11, 9))
      best =
          std::min(best, WorstError(*detection, TruePixels(camera, *board, T_cam_target), relabel));
    CHECK(best < 0.3);
    CHECK(mismatch.empty());
  }
}

TEST_CASE("A transposed declaration with an even side reads the board turned, with no mismatch",
          "[checkerboard][transposed]") {
  // 6 x 5 declared [5, 6]: the board turned a quarter has a black square at
  // its new corner (0, 0), so it is the declared board seen turned, and the
  // calibration is unaffected (its target frame is an unknown).
  const Camera camera = MakeTestCamera(640, 480, 640.0, MildDistortion());
  auto board = std::make_shared<const CheckerboardTarget>(6, 5, 0.04);
  const auto declared = MakeDetector(std::make_shared<const CheckerboardTarget>(5, 6, 0.04));
  const Eigen::Isometry3d T_cam_target = BoardPose(*board, 0.7, 0.2, 0.3, {1, 0.5}, {0.0, 0.01});
  RenderOptions options;
  options.seed = 50;
  std::string mismatch = "stale";
  const auto detection =
      declared->DetectOrExplain(RenderView(camera, *board, T_cam_target, options), &mismatch);
  REQUIRE(detection);
  CHECK(detection->ids.size() == 30);
  CHECK(mismatch.empty());
}
