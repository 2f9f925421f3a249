// SPDX-License-Identifier: GPL-2.0-or-later
// ChArUco plugin: the print agrees with OpenCV 4.6's own drawing, and the
// detector finds the corners of rendered views (with lens-free pinhole
// cameras, clutter, blur and noise) accurately, with no wrong ids.
#include "handeye/detectors/charuco_detector.h"

#include <array>
#include <map>
#include <tuple>
#include <catch2/catch.hpp>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/imgproc.hpp>

#include "detectors/rendered_views.h"
#include "handeye/core/error.h"
#include "handeye/detectors/registry.h"

using namespace handeye;

namespace {

constexpr double kSquareM = 0.055, kMarkerM = 0.04;

TargetSpec BoardSpec(int sx = 7, int sy = 5, const std::string& dictionary = "DICT_5X5_100") {
  TargetSpec spec;
  spec.type = "charuco";
  spec.values["squares"] = std::vector<double>{double(sx), double(sy)};
  spec.values["square_size_m"] = kSquareM;
  spec.values["marker_size_m"] = kMarkerM;
  spec.values["dictionary"] = dictionary;
  return spec;
}

test::ViewSampling CharucoSampling(double min_px, double max_px) {
  test::ViewSampling sampling;
  sampling.feature_m = kMarkerM;
  sampling.min_feature_px = min_px;
  sampling.max_feature_px = max_px;
  return sampling;
}

// Wrong id: farther from its true corner than a quarter of the smallest
// square (20 px markers: 27 px squares); scoring margin: 6 px.
constexpr double kCharucoWrongPx = 3.0, kCharucoBorderPx = 6.0;

double Mean(const std::vector<double>& values) {
  double sum = 0;
  for (double v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

}  // namespace

TEST_CASE("ArUco code books are the markers cv::aruco::drawMarker draws", "[charuco]") {
  const std::vector<std::string> names = ArucoDictionaryNames();
  REQUIRE(names.size() == 21);
  for (std::size_t index = 0; index < names.size(); ++index) {
    // OpenCV numbers its predefined dictionaries in this order (DICT_4X4_50 = 0).
    INFO(names[index]);
    const MarkerCodebook book = ArucoCodebook(names[index]);
    REQUIRE(book.Valid());
    const auto dictionary = cv::aruco::getPredefinedDictionary(static_cast<int>(index));
    REQUIRE(book.bits == dictionary->markerSize);
    REQUIRE(static_cast<int>(book.codes.size()) == dictionary->bytesList.rows);
    const int n = book.bits, cell = 10;
    for (int id : {0, 1, static_cast<int>(book.codes.size()) - 1}) {
      cv::Mat drawn;
      cv::aruco::drawMarker(dictionary, id, (n + 2) * cell, drawn, 1);
      for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
          CHECK((drawn.at<std::uint8_t>((r + 1) * cell + cell / 2, (c + 1) * cell + cell / 2) >
                 127) == (book.codes[id][r * n + c] == 1));
    }
  }
}

TEST_CASE("charuco print matches cv::aruco::CharucoBoard::draw of OpenCV 4.6", "[charuco]") {
  // 5x4 squares: an even row count, where pre-4.6 boards differ.
  for (const auto& [sx, sy] : {std::pair<int, int>{5, 4}, {7, 5}}) {
    INFO(sx << "x" << sy);
    const auto board = MakeCharucoTarget(BoardSpec(sx, sy, "DICT_4X4_50"));
    const auto cv_board = cv::aruco::CharucoBoard::create(
        sx, sy, static_cast<float>(kSquareM), static_cast<float>(kMarkerM),
        cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50));
    constexpr int kPxPerSquare = 110;
    cv::Mat drawn;
    cv_board->draw(cv::Size(sx * kPxPerSquare, sy * kPxPerSquare), drawn, 0, 1);
    int mismatched = 0, interior = 0;
    const double pitch = kSquareM / kPxPerSquare;
    const double cell = kMarkerM / 6;  // 4 bits + border
    for (int r = 0; r < drawn.rows; ++r) {
      for (int c = 0; c < drawn.cols; ++c) {
        const double x = (c + 0.5) * pitch, y = (r + 0.5) * pitch;
        // Skip pixels within 1.5 px of a square or marker-cell boundary,
        // where OpenCV's integer drawing rounds.
        auto near = [&](double v, double period, double offset) {
          const double t = std::fmod(v - offset + 100 * period, period);
          return std::min(t, period - t) < 1.5 * pitch;
        };
        // Cell boundaries repeat within each square, from the marker's edge.
        const double margin = 0.5 * (kSquareM - kMarkerM);
        const double x_in = std::fmod(x, kSquareM) - margin, y_in = std::fmod(y, kSquareM) - margin;
        if (near(x, kSquareM, 0) || near(y, kSquareM, 0) || near(x_in, cell, 0) ||
            near(y_in, cell, 0))
          continue;
        ++interior;
        mismatched += (board->Albedo(x, y) > 0.5) != (drawn.at<std::uint8_t>(r, c) > 127);
      }
    }
    CHECK(interior > static_cast<int>(drawn.total() / 2));
    CHECK(mismatched == 0);
  }
}

TEST_CASE("charuco and aprilgrid are registered target plugins", "[charuco][registry]") {
  const auto types = KnownTargetTypes();
  CHECK(std::find(types.begin(), types.end(), "charuco") != types.end());
  const auto target = MakeTarget(BoardSpec());
  CHECK(dynamic_cast<const CharucoTarget*>(target.get()));
  CHECK(dynamic_cast<const CharucoDetector*>(MakeDetector(target).get()));
}

TEST_CASE("charuco spec errors: unknown dictionary lists OpenCV's, too small a dictionary",
          "[charuco]") {
  auto error_of = [](const TargetSpec& spec) -> std::string {
    try {
      MakeTarget(spec);
    } catch (const InputError& e) {
      return e.json_path() + ": " + e.expected();
    }
    return "";
  };
  CHECK_THAT(error_of(BoardSpec(7, 5, "DICT_5X5_99")),
             Catch::Contains("/dictionary") && Catch::Contains("DICT_APRILTAG_36h11"));
  CHECK_THAT(error_of(BoardSpec(11, 11, "DICT_4X4_50")), Catch::Contains("needs 60 markers"));
  TargetSpec no_dictionary = BoardSpec();
  no_dictionary.values.erase("dictionary");
  CHECK_THAT(error_of(no_dictionary), Catch::Contains("/dictionary"));
}

TEST_CASE("charuco corners at 1280x720 and 1920x1080: >= 99 % found, mean error <= 0.1 px",
          "[charuco][accuracy]") {
  const auto board = MakeCharucoTarget(BoardSpec());
  const CharucoDetector detector(board);
  RenderOptions render;
  for (const auto& [width, height] : {std::pair<int, int>{1280, 720}, {1920, 1080}}) {
    INFO(width << "x" << height);
    const Camera camera = test::PinholeCamera(width, height, 0.714 * width);
    const test::Score score =
        test::RenderAndScore(camera, *board, detector, test::CharucoMarkers(*board),
                             CharucoSampling(20, 40), render, 12, width, kCharucoBorderPx, kCharucoWrongPx, 8);
    INFO(score.Summary());
    CHECK(score.expected > 100);
    CHECK(score.Rate() >= 0.99);
    CHECK(score.MeanError() <= 0.1);
    CHECK(score.wrong == 0);
  }
}

TEST_CASE("charuco partial views: half the board outside the image, ids still right",
          "[charuco][partial]") {
  // A 10x8 board, so that half of it still holds a good number of corners.
  const auto board = MakeCharucoTarget(BoardSpec(10, 8));
  const CharucoDetector detector(board);
  const Camera camera = test::PinholeCamera(1280, 720, 900);
  const double distance = 900 * kMarkerM / 30;  // 30 px markers
  test::Score score;
  int views = 0;
  // The sheet's centre on each edge of the image, turned a little.
  for (const auto& [u, v] :
       {std::pair<double, double>{0, 360}, {1279, 360}, {640, 0}, {640, 719}}) {
    const Eigen::Isometry3d T = test::ViewAt(camera, *board, u, v, distance, 0.1 * views, 0.2);
    RenderOptions render;
    render.seed = 40 + views++;
    const auto detection = detector.Detect(RenderView(camera, *board, T, render));
    REQUIRE(detection);
    CHECK(detection->ids.size() >= 12);
    CHECK(detection->ids.size() <= board->Points().size() / 2 + 9);
    test::ScoreView(camera, *board, T, test::CharucoMarkers(*board), detection, 20, kCharucoBorderPx, 0.5,
                    8, &score);
  }
  INFO(score.Summary());
  CHECK(score.wrong == 0);  // every id within 0.5 px of its true corner
  CHECK(score.Rate() >= 0.99);
}

TEST_CASE("charuco: no wrong ids over 200 rendered 640x480 views", "[charuco][ids]") {
  const auto board = MakeCharucoTarget(BoardSpec());
  const CharucoDetector detector(board);
  const Camera camera = test::PinholeCamera(640, 480, 0.714 * 640);
  test::ViewSampling sampling = CharucoSampling(14, 60);  // also below 20 px, where misreads would start
  sampling.max_tilt_deg = 60;
  sampling.centre_beyond_border = 0.3;
  const test::Score score =
      test::RenderAndScore(camera, *board, detector, test::CharucoMarkers(*board), sampling,
                           RenderOptions(), 200, 2024, kCharucoBorderPx, kCharucoWrongPx, 8);
  INFO(score.Summary());
  CHECK(score.views_detected >= 40);
  CHECK(score.found >= 400);
  CHECK(score.wrong == 0);
  CHECK(score.Rate() >= 0.99);
}

TEST_CASE("charuco: corners next to misplaced markers fail the local homography; the black squares place them",
          "[charuco][homography]") {
  // A misprinted board, markers 2 and 12 swapped: OpenCV's interpolation puts
  // the corners around them (and their neighbours) in the wrong place, as
  // OpenCV 4.6 also does on its own (opencv_contrib issues 3301, 3367). The
  // two markers of such a corner do not fit one homography, and the corner is
  // not taken from them; the lattice of black squares, placed by the other
  // 15 markers (two disagreeing against 15 agreeing), puts each where it is.
  const auto board = MakeCharucoTarget(BoardSpec());
  MarkerCodebook swapped = board->dictionary();
  std::swap(swapped.codes[2], swapped.codes[12]);
  const CharucoTarget misprint(BoardSpec(), swapped);
  const CharucoDetector detector(board);
  const Camera camera = test::PinholeCamera(1280, 720, 900);
  test::Score score;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Isometry3d T =
        test::ViewAt(camera, misprint, 640 + 40 * k, 360, 900 * kMarkerM / 35, 0.4 * k, 0.2 * k);
    RenderOptions render;
    render.seed = 70 + k;
    const auto detection = detector.Detect(RenderView(camera, misprint, T, render));
    test::ScoreView(camera, *board, T, test::CharucoMarkers(*board), detection, 20, kCharucoBorderPx, 1.0,
                    8, &score);
  }
  INFO(score.Summary());
  CHECK(score.wrong == 0);
  CHECK(score.found == score.expected);
}

TEST_CASE("charuco: corners all on one line are no view; min_corners from the target",
          "[charuco]") {
  const Camera camera = test::PinholeCamera(1280, 720, 900);
  RenderOptions render;
  {
    // 8x2 squares: seven corners, all on one line.
    TargetSpec spec = BoardSpec(8, 2);
    spec.values["min_corners"] = 4.0;
    const auto strip = MakeCharucoTarget(spec);
    const CharucoDetector detector(strip);
    const auto T = test::ViewAt(camera, *strip, 640, 360, 900 * kMarkerM / 35, 0.1, 0.1);
    std::vector<CharucoRejection> rejected;
    CHECK_FALSE(detector.Detect(RenderView(camera, *strip, T, render), &rejected));
    CHECK(rejected.empty());  // found, refined and consistent, but collinear
  }
  {
    TargetSpec spec = BoardSpec();
    spec.values["min_corners"] = 25.0;  // more than the 24 on the board
    const auto board = MakeCharucoTarget(spec);
    const auto T = test::ViewAt(camera, *board, 640, 360, 900 * kMarkerM / 35, 0.1, 0.1);
    const cv::Mat image = RenderView(camera, *board, T, render);
    CHECK_FALSE(CharucoDetector(board).Detect(image));
    CharucoDetector::Options options;
    const auto detection = CharucoDetector(board, options).Detect(image);
    REQUIRE(detection);
    CHECK(detection->ids.size() == 24);
  }
}

namespace {

/// What the detector of `declared` found in 12 rendered views of `printed`
/// (both the 7x5 board unless given) from a cell camera (1920x1080, fx
/// 1371): squares `square_px` wide face-on, tilted
/// from `first_deg` over `span_deg`, centred near the image centre (offsets
/// `step_px` apart), blur and noise growing from view to view.
struct ObliqueViews {
  int found = 0, complete = 0, corners = 0, wrong = 0;
  std::vector<double> errors;
  std::map<int, std::vector<double>> errors_by_5_deg;  ///< tilt rounded down to 5 degrees
};

ObliqueViews DetectObliqueViews(double square_px, double first_deg, double span_deg,
                                const Eigen::Vector2d& step_px, double spin_rad, unsigned seed,
                                const TargetSpec& printed = BoardSpec(),
                                const TargetSpec& declared = BoardSpec()) {
  const auto board = MakeCharucoTarget(printed);
  const CharucoDetector detector(MakeCharucoTarget(declared));
  const Camera camera = test::PinholeCamera(1920, 1080, 1371);
  const double distance = 1371 * kSquareM / square_px;
  ObliqueViews views;
  for (int k = 0; k < 12; ++k) {
    const double tilt_deg = first_deg + span_deg * (k + 0.5) / 12;
    const Eigen::Isometry3d T =
        test::ViewAt(camera, *board, 960 + step_px.x() * (k % 3), 540 - step_px.y() * (k % 4),
                     distance, 2 * M_PI * k / 12 + spin_rad, tilt_deg * M_PI / 180);
    RenderOptions render;
    render.blur_sigma_px = 0.6 + 0.05 * k;
    render.noise_sigma = 2 + 0.3 * k;
    render.seed = seed + k;
    const auto detection = detector.Detect(RenderView(camera, *board, T, render));
    if (!detection) continue;
    ++views.found;
    views.complete += detection->ids.size() == board->Points().size();
    for (std::size_t i = 0; i < detection->ids.size(); ++i) {
      const auto truth = camera.Project(T * board->FindPoint(detection->ids[i])->p_target);
      const double error = truth ? (detection->points_px[i] - *truth).norm() : 1e9;
      if (error > kCharucoWrongPx) {
        ++views.wrong;
        continue;
      }
      ++views.corners;
      views.errors.push_back(error);
      views.errors_by_5_deg[5 * static_cast<int>(tilt_deg / 5)].push_back(error);
    }
  }
  return views;
}

}  // namespace

TEST_CASE("charuco seen at 60-70 degrees: the decoded markers number the corners of the rest",
          "[charuco][oblique]") {
  // A cell camera (1920x1080, fx 1371) sees a 7x5 board of 28 px squares
  // (20 px markers, 2.9 px per bit) face-on; tilted by 60-70 degrees its far
  // markers no longer decode, so the corners between two decoded markers
  // were all that was found. Every corner of a view found is one square from
  // others on the board: grown from the decoded markers, all 24 are found in
  // the 5 views where three markers decode. In the other 7 (fewer markers
  // decode, up to none) the black squares number the corners. The markers
  // are left out of each corner's window as the image shows them (they were
  // grown on the board by 2 px of the narrow direction, which beyond 65
  // degrees covered the corner: 0.27 px mean error there, 4 views short of
  // all 24 corners).
  const ObliqueViews views = DetectObliqueViews(28, 60, 10, {40, 30}, 0.2, 700);
  INFO(views.found << " of 12 views found, " << views.complete << " with all corners, "
                   << views.wrong << " wrong ids, mean error " << Mean(views.errors)
                   << " px (60-65 degrees " << Mean(views.errors_by_5_deg.at(60)) << ", 65-70 "
                   << Mean(views.errors_by_5_deg.at(65)) << ")");
  CHECK(views.found == 12);
  CHECK(views.complete == 12);
  CHECK(views.wrong == 0);
  CHECK(Mean(views.errors_by_5_deg.at(60)) <= 0.1);
  CHECK(Mean(views.errors_by_5_deg.at(65)) <= 0.15);
}

TEST_CASE("charuco too far for its markers to decode: the black squares and the markers' grey levels number the corners",
          "[charuco][oblique]") {
  // The cell camera of the test above farther away: 18 px squares, 13 px
  // markers, 1.9 px per bit face-on, a pixel or less across the tilt at
  // 45-65 degrees, blurred and noisy. OpenCV decodes none or few of the
  // markers beyond 50 degrees (4 views of 12 found, 96 corners), but it finds
  // the black squares as quadrilaterals; joined corner to corner they are a
  // lattice, and the markers' grey levels say where on the board it lies.
  const ObliqueViews views = DetectObliqueViews(18, 45, 20, {120, 80}, 0.4, 900);
  INFO(views.found << " of 12 views found, " << views.corners << " of 288 corners, "
                   << views.wrong << " wrong ids, mean error " << Mean(views.errors) << " px");
  CHECK(views.found >= 10);
  CHECK(views.corners >= 240);
  CHECK(views.wrong == 0);
  CHECK(Mean(views.errors) <= 0.2);
}

TEST_CASE("charuco too far to decode: a print of other markers, the other way round or old-style is not numbered from its squares",
          "[charuco][oblique]") {
  // The views of the test above, of prints that are not the board declared:
  // their black squares form the same lattice (or the one turned, or one
  // shifted by a square), but the grey levels at the markers follow no
  // placement of the declared print (correlation under 0.16 where the
  // board's own gives 0.40-0.89), or another layout explains them as well
  // with fewer squares off the board, and that layout is named. An
  // old-style print (OpenCV before 4.6: square (0, 0) white with an even
  // number of rows) is today's board shifted by a square but for three
  // markers: declared in today's layout it gave a view of 30 corners, every
  // one a square off, through 12 decoded markers.
  auto other_markers = BoardSpec();
  other_markers.values["dictionary"] = std::string("DICT_4X4_50");
  auto old_style = BoardSpec(7, 6);
  old_style.values["layout"] = std::string("legacy");
  const std::vector<std::tuple<std::string, TargetSpec, TargetSpec>> cases = {
      {"DICT_4X4_50 print of the 7x5 board", other_markers, BoardSpec()},
      {"5x7 print of the 7x5 board", BoardSpec(5, 7), BoardSpec()},
      {"old-style print of the 7x6 board", old_style, BoardSpec(7, 6)}};
  for (const auto& [name, printed, declared] : cases) {
    const ObliqueViews views =
        DetectObliqueViews(18, 45, 20, {120, 80}, 0.4, 900, printed, declared);
    INFO(name << ": " << views.found << " of 12 views found, " << views.corners + views.wrong
              << " corners");
    CHECK(views.corners + views.wrong == 0);
  }
  // The 7x6 board printed as declared is still found.
  const ObliqueViews views = DetectObliqueViews(18, 45, 20, {120, 80}, 0.4, 900, BoardSpec(7, 6),
                                                BoardSpec(7, 6));
  INFO("7x6 board: " << views.found << " of 12 views found, " << views.corners << " corners, "
                     << views.wrong << " wrong");
  CHECK(views.found >= 10);
  CHECK(views.wrong == 0);
}

TEST_CASE("charuco board with fewer than eight corners is found without a min_corners of its own",
          "[charuco][small]") {
  // The default of eight corners (and the first stage's 3 x 2 block of
  // corners) could never be met by a board of 3 x 3 squares (four corners)
  // or 4 x 3 (six, in a 3 x 2 block): such boards found nothing.
  RenderOptions render;
  render.clutter = false;
  for (const auto& [sx, sy] : {std::pair<int, int>{3, 3}, {4, 3}, {3, 4}}) {
    const auto board = MakeCharucoTarget(BoardSpec(sx, sy));
    const CharucoDetector detector(board);
    const std::size_t all = board->Points().size();
    for (const auto& [width, height] : {std::pair<int, int>{640, 480}, {1280, 720}}) {
      const Camera camera = test::PinholeCamera(width, height, 0.8 * width);
      for (const double tilt : {0.0, 0.5}) {
        CAPTURE(sx, sy, width, tilt);
        const Eigen::Isometry3d T = test::ViewAt(camera, *board, width / 2.0, height / 2.0,
                                                 0.8 * width * kMarkerM / 60, 0.3, tilt);
        const auto detection = detector.Detect(RenderView(camera, *board, T, render));
        REQUIRE(detection);
        REQUIRE(detection->ids.size() == all);
        for (std::size_t i = 0; i < all; ++i)
          CHECK((detection->points_px[i] -
                 *camera.Project(T * board->FindPoint(detection->ids[i])->p_target))
                    .norm() < 0.3);
      }
    }
  }
}
