// SPDX-License-Identifier: GPL-2.0-or-later
// ChArUco boards as users printed them: the layout of OpenCV before 4.6
// (`layout` "legacy") is read with the right ids, and a print whose layout
// or squares differ from the declared ones is named with what to change.
#include "../../detectors/src/charuco_layout.h"

#include <catch2/catch.hpp>
#include <opencv2/aruco/charuco.hpp>

#include "detectors/rendered_views.h"
#include "handeye/core/error.h"
#include "handeye/detectors/charuco_detector.h"

using namespace handeye;
using Catch::Matchers::Contains;

namespace {

constexpr double kLayoutSquareM = 0.055, kLayoutMarkerM = 0.04;

TargetSpec Spec(int sx, int sy, const std::string& layout = "") {
  TargetSpec spec;
  spec.type = "charuco";
  spec.values["squares"] = std::vector<double>{double(sx), double(sy)};
  spec.values["square_size_m"] = kLayoutSquareM;
  spec.values["marker_size_m"] = kLayoutMarkerM;
  spec.values["dictionary"] = std::string("DICT_5X5_100");
  if (!layout.empty()) spec.values["layout"] = layout;
  return spec;
}

/// Three rendered 640x480 views of `print` (markers of about 35 px, turned and tilted).
std::vector<std::pair<Eigen::Isometry3d, cv::Mat>> Views(const Camera& camera,
                                                         const CharucoTarget& print) {
  std::vector<std::pair<Eigen::Isometry3d, cv::Mat>> views;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Isometry3d T = test::ViewAt(camera, print, 320 + 20 * k, 240 - 10 * k,
                                             camera.fx() * kLayoutMarkerM / 35, 0.5 * k - 0.3, 0.25 * k);
    RenderOptions render;
    render.seed = 90 + k;
    views.emplace_back(T, RenderView(camera, print, T, render));
  }
  return views;
}

}  // namespace

TEST_CASE(
    "charuco legacy layout: square (0, 0) white with an even row count, the same board with an odd "
    "one",
    "[charuco][legacy]") {
  const auto legacy = MakeCharucoTarget(Spec(6, 4, "legacy"));
  const auto current = MakeCharucoTarget(Spec(6, 4));
  CHECK(legacy->legacy());
  CHECK(legacy->MarkerInSquare(0, 0) == 0);
  CHECK(legacy->MarkerInSquare(1, 0) == -1);
  CHECK(legacy->Albedo(1.5 * kLayoutSquareM, 0.5 * kLayoutSquareM) == 0.0);
  CHECK(current->MarkerInSquare(0, 0) == -1);
  CHECK(current->MarkerInSquare(1, 0) == 0);
  CHECK(legacy->NumMarkers() == current->NumMarkers());
  CHECK(legacy->Points().size() == current->Points().size());
  // An odd row count: OpenCV's two layouts are one board.
  const auto legacy_odd = MakeCharucoTarget(Spec(7, 5, "legacy"));
  const auto current_odd = MakeCharucoTarget(Spec(7, 5));
  for (int b = 0; b < 5; ++b)
    for (int a = 0; a < 7; ++a)
      CHECK(legacy_odd->MarkerInSquare(a, b) == current_odd->MarkerInSquare(a, b));
  try {
    MakeCharucoTarget(Spec(6, 4, "old"));
    FAIL("no error for layout \"old\"");
  } catch (const InputError& e) {
    CHECK(e.json_path() == "/layout");
    CHECK_THAT(e.expected(), Contains("\"legacy\""));
  }
}

TEST_CASE("charuco: the markers laid out from the target are OpenCV 4.6's own board for its layout",
          "[charuco][legacy]") {
  for (const auto& [sx, sy] : {std::pair<int, int>{5, 4}, {7, 5}, {6, 6}}) {
    INFO(sx << "x" << sy);
    const auto target = MakeCharucoTarget(Spec(sx, sy));
    const auto opencv = cv::aruco::CharucoBoard::create(
        sx, sy, 1.0f, static_cast<float>(kLayoutMarkerM / kLayoutSquareM),
        cv::aruco::getPredefinedDictionary(cv::aruco::DICT_5X5_100));
    cv::aruco::CharucoBoard ours = *opencv;
    ours.objPoints.clear();
    ours.nearestMarkerIdx.clear();
    ours.nearestMarkerCorners.clear();
    internal::LayOutMarkers(*target, &ours);
    REQUIRE(ours.objPoints.size() == opencv->objPoints.size());
    for (std::size_t m = 0; m < ours.objPoints.size(); ++m)
      for (int k = 0; k < 4; ++k)
        CHECK(cv::norm(ours.objPoints[m][k] - opencv->objPoints[m][k]) < 1e-5);
    CHECK(ours.nearestMarkerIdx == opencv->nearestMarkerIdx);
    CHECK(ours.nearestMarkerCorners == opencv->nearestMarkerCorners);
  }
}

TEST_CASE("charuco: a print of OpenCV before 4.6 is read with layout legacy and named without it",
          "[charuco][legacy]") {
  const Camera camera = test::PinholeCamera(640, 480, 0.714 * 640);
  const auto print = MakeCharucoTarget(Spec(6, 4, "legacy"));
  const CharucoDetector legacy(print);
  const CharucoDetector declared_current(MakeCharucoTarget(Spec(6, 4)));
  test::Score score;
  for (const auto& [T, image] : Views(camera, *print)) {
    std::string mismatch = "stale";
    const auto detection = legacy.DetectOrExplain(image, &mismatch);
    CHECK(detection);
    CHECK(mismatch.empty());
    test::ScoreView(camera, *print, T, test::CharucoMarkers(*print), detection, 20, 6.0, 3.0, 8,
                    &score);
    CHECK_FALSE(declared_current.DetectOrExplain(image, &mismatch));
    CHECK_THAT(mismatch, Contains("an old-style print (OpenCV before 4.6") &&
                             Contains("add \"layout\": \"legacy\" to the target"));
  }
  INFO(score.Summary());
  CHECK(score.expected >= 3 * 12);
  CHECK(score.wrong == 0);
  CHECK(score.Rate() >= 0.95);
  // The other way round: a current print declared legacy.
  const auto current = MakeCharucoTarget(Spec(6, 4));
  std::string mismatch;
  CHECK_FALSE(legacy.DetectOrExplain(Views(camera, *current)[0].second, &mismatch));
  CHECK_THAT(mismatch, Contains("laid out as OpenCV 4.6 and later print it") &&
                           Contains("\"layout\": \"legacy\": remove it"));
}

TEST_CASE("charuco: squares declared the wrong way round are named", "[charuco][transposed]") {
  const Camera camera = test::PinholeCamera(640, 480, 0.714 * 640);
  const auto print = MakeCharucoTarget(Spec(5, 7));
  const CharucoDetector declared(MakeCharucoTarget(Spec(7, 5)));
  const CharucoDetector right(print);
  for (const auto& [T, image] : Views(camera, *print)) {
    std::string mismatch;
    CHECK_FALSE(declared.DetectOrExplain(image, &mismatch));
    CHECK(mismatch ==
          "the ChArUco board in the images has 5x7 squares; the target declares squares [7, 5]: "
          "swap it to [5, 7]");
    CHECK(right.DetectOrExplain(image, &mismatch));
    CHECK(mismatch.empty());
  }
}
