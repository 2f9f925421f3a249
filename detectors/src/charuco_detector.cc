// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/detectors/charuco_detector.h"

#include <Eigen/SVD>
#include <algorithm>
#include <limits>
#include <map>
#include <opencv2/aruco/charuco.hpp>
#include <set>
#include <stdexcept>
#include <utility>
#include <variant>

#include "charuco_growth.h"
#include "charuco_layout.h"
#include "charuco_squares.h"
#include "corner_refinement.h"
#include "grid_patch.h"
#include "handeye/core/error.h"
#include "target_options.h"

namespace handeye {
namespace {

const std::vector<std::pair<std::string, cv::aruco::PREDEFINED_DICTIONARY_NAME>>& Dictionaries() {
  using namespace cv::aruco;
  static const std::vector<std::pair<std::string, PREDEFINED_DICTIONARY_NAME>> table = {
      {"DICT_4X4_50", DICT_4X4_50},
      {"DICT_4X4_100", DICT_4X4_100},
      {"DICT_4X4_250", DICT_4X4_250},
      {"DICT_4X4_1000", DICT_4X4_1000},
      {"DICT_5X5_50", DICT_5X5_50},
      {"DICT_5X5_100", DICT_5X5_100},
      {"DICT_5X5_250", DICT_5X5_250},
      {"DICT_5X5_1000", DICT_5X5_1000},
      {"DICT_6X6_50", DICT_6X6_50},
      {"DICT_6X6_100", DICT_6X6_100},
      {"DICT_6X6_250", DICT_6X6_250},
      {"DICT_6X6_1000", DICT_6X6_1000},
      {"DICT_7X7_50", DICT_7X7_50},
      {"DICT_7X7_100", DICT_7X7_100},
      {"DICT_7X7_250", DICT_7X7_250},
      {"DICT_7X7_1000", DICT_7X7_1000},
      {"DICT_ARUCO_ORIGINAL", DICT_ARUCO_ORIGINAL},
      {"DICT_APRILTAG_16h5", DICT_APRILTAG_16h5},
      {"DICT_APRILTAG_25h9", DICT_APRILTAG_25h9},
      {"DICT_APRILTAG_36h10", DICT_APRILTAG_36h10},
      {"DICT_APRILTAG_36h11", DICT_APRILTAG_36h11},
  };
  return table;
}

cv::Ptr<cv::aruco::Dictionary> PredefinedDictionary(const std::string& name) {
  for (const auto& [known, id] : Dictionaries())
    if (known == name) return cv::aruco::getPredefinedDictionary(id);
  std::string list;
  for (const auto& [known, id] : Dictionaries()) list += (list.empty() ? "" : ", ") + known;
  throw InputError("", "/dictionary",
                   "unknown dictionary '" + name + "'; expected one of OpenCV's: " + list);
}

Eigen::Vector2d ToEigen(const cv::Point2f& p) { return {p.x, p.y}; }

/// Squares narrower than this (pixels, most foreshortened direction) leave
/// too few pixels between the markers for a trustworthy X junction. (8 px
/// while the markers were left out grown on the board rather than in the
/// image: at 70-75 degrees that left most corners out; with 5 px, recall
/// there went from 41 to 51 % on bench_detect_targets --by-angle 40, no
/// wrong id.)
constexpr double kMinSquarePx = 5.0;
/// Refinement window: radius in squares, and its cap in pixels.
constexpr double kWindowSquares = 0.6;
constexpr double kMaxWindowPx = 30.0;
/// A view that fails with at least this many markers decoded is checked
/// against other layouts than the declared one (OtherLayouts): fewer fit
/// any layout too easily.
constexpr std::size_t kMinMarkersToJudgeLayout = 6;
/// Another layout explains the black squares better where it leaves at
/// least this many fewer of them off the board and its correlation with the
/// print is no more than kMisfitTieCorrelation below the declared one's.
constexpr int kMisfitLead = 2;
constexpr double kMisfitTieCorrelation = 0.05;

/// True when the black squares fit placement `a` (on one layout) clearly
/// better than `b` (on another): the markers' grey levels follow it
/// internal::kMinLead better, or as well with kMisfitLead fewer squares off
/// the board. An old-style print of an even number of rows is today's board
/// shifted by a square (its markers too, but for one per two rows), so the
/// grey levels hardly tell the two apart; the column of squares the shift
/// leaves off the board does.
bool ClearlyAhead(const internal::SquaresPlacement& a, const internal::SquaresPlacement& b) {
  return a.correlation >= b.correlation + internal::kMinLead ||
         (a.misfits + kMisfitLead <= b.misfits &&
          a.correlation >= b.correlation - kMisfitTieCorrelation);
}
/// A square of the board at `xy` (metres) in the image under `H`: its two
/// sides as columns, and the smaller singular value, its extent along its
/// most foreshortened direction (pixels).
std::pair<Eigen::Matrix2d, double> SquareInImage(const Eigen::Matrix3d& H,
                                                 const Eigen::Vector2d& xy, double L) {
  const Eigen::Vector2d at = internal::ApplyHomography(H, xy);
  Eigen::Matrix2d square;
  square.col(0) = internal::ApplyHomography(H, xy + Eigen::Vector2d(L, 0)) - at;
  square.col(1) = internal::ApplyHomography(H, xy + Eigen::Vector2d(0, L)) - at;
  return {square, Eigen::JacobiSVD<Eigen::Matrix2d>(square).singularValues()(1)};
}

/// How far a corner may lie from its prediction where the square is
/// `square_px` across (CharucoDetector::Options).
double HomographyTolerancePx(const CharucoDetector::Options& options, double square_px) {
  return std::max(options.min_homography_tolerance_px, options.homography_tolerance * square_px);
}

/// Pixels within this distance of a marker's outline (blur and the gradient
/// stencil) are left out of a corner's refinement.
constexpr double kMarkerGuardPx = 2.0;

/// How far `p` lies outside the convex quadrilateral `quad` (either winding);
/// 0 inside.
double DistanceOutside(const std::array<Eigen::Vector2d, 4>& quad, const Eigen::Vector2d& p) {
  const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  int positive = 0, negative = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d a = quad[k], edge = quad[(k + 1) % 4] - a;
    (cross(edge, p - a) >= 0 ? positive : negative) += 1;
    const double t = std::clamp((p - a).dot(edge) / edge.squaredNorm(), 0.0, 1.0);
    nearest = std::min(nearest, (a + t * edge - p).norm());
  }
  return positive == 4 || negative == 4 ? 0.0 : nearest;
}
/// A corner the black squares placed too far from its X-junction is
/// predicted again from the corners found within this many squares (along
/// each board axis), when there are at least kMinRepredictSupport of them.
constexpr double kRepredictSquares = 2.0;
constexpr std::size_t kMinRepredictSupport = 5;
/// A corner farther than this many homography tolerances from where the
/// corners around it put it is dropped (DropCornersOffTheirNeighbours). One
/// tolerance dropped good corners of squeezed boards (recall at 70-75 degrees
/// 51 -> 50 %); the wrong one it was for lay 3.3 px off, 1.5 keeps it out.
constexpr double kNeighbourToleranceShare = 1.5;

/// The homography (board metres to pixels) of the corners in `known` (ids,
/// pixels) within kRepredictSquares of corner `id` along each board axis,
/// `id` itself left out; nullopt with fewer than kMinRepredictSupport.
std::optional<Eigen::Matrix3d> NeighbourHomography(const CharucoTarget& target,
                                                   const std::map<int, Eigen::Vector2d>& known,
                                                   int id) {
  const double L = target.square_size_m();
  const Eigen::Vector2d xy = target.FindPoint(id)->p_target.head<2>();
  std::vector<Eigen::Vector2d> board, image;
  for (const auto& [other, uv] : known) {
    if (other == id) continue;
    const Eigen::Vector2d other_xy = target.FindPoint(other)->p_target.head<2>();
    if (((other_xy - xy).cwiseAbs() / L).maxCoeff() > kRepredictSquares) continue;
    board.push_back(other_xy);
    image.push_back(uv);
  }
  if (board.size() < kMinRepredictSupport) return std::nullopt;
  return internal::FitHomography(board, image);
}

/// Adds to `found` (ids, pixels) the corners the black squares `placed`
/// (internal::PlaceCornersBySquares) that are not in it yet, refined by
/// `refine` (internal::CharucoCornerRefiner).
void AddPlacedCorners(const CharucoTarget& target,
                      const std::vector<internal::PlacedCorner>& placed,
                      const internal::CharucoCornerRefiner& refine,
                      std::vector<std::pair<int, Eigen::Vector2d>>* found) {
  std::map<int, Eigen::Vector2d> known(found->begin(), found->end());
  std::vector<internal::PlacedCorner> left;
  std::set<int> squares_placed;
  for (const auto& corner : placed) {
    if (known.count(corner.id)) continue;
    if (const auto uv = refine(corner.id, corner.H_image_target, corner.guess_px)) {
      found->emplace_back(corner.id, *uv);
      known[corner.id] = *uv;
      squares_placed.insert(corner.id);
    } else {
      left.push_back(corner);
    }
  }
  // The squares' quadrilaterals place a corner to a pixel or so: its window
  // and the markers it leaves out follow that homography. Each corner is
  // refined once more with the homography of the corners refined around it
  // (as the growth from decoded markers does), and one placed too far from
  // its X-junction is found that way.
  const auto refit = [&](int id) { return NeighbourHomography(target, known, id); };
  for (auto& [id, uv] : *found) {
    if (!squares_placed.count(id)) continue;
    const auto H = refit(id);
    if (!H) continue;
    if (const auto again = refine(id, *H, uv)) uv = *again;
  }
  for (const auto& [id, uv] : *found) known[id] = uv;
  for (bool grew = true; grew && !left.empty();) {
    grew = false;
    for (auto it = left.begin(); it != left.end();) {
      const auto H = refit(it->id);
      if (H) {
        const Eigen::Vector2d xy = target.FindPoint(it->id)->p_target.head<2>();
        if (const auto uv = refine(it->id, *H, internal::ApplyHomography(*H, xy))) {
          found->emplace_back(it->id, *uv);
          known[it->id] = *uv;
          it = left.erase(it);
          grew = true;
          continue;
        }
      }
      ++it;
    }
  }
}

}  // namespace

std::vector<std::string> ArucoDictionaryNames() {
  std::vector<std::string> names;
  for (const auto& [name, id] : Dictionaries()) names.push_back(name);
  return names;
}

MarkerCodebook ArucoCodebook(const std::string& dictionary_name) {
  const cv::Ptr<cv::aruco::Dictionary> dictionary = PredefinedDictionary(dictionary_name);
  MarkerCodebook book;
  book.name = dictionary_name;
  book.bits = dictionary->markerSize;
  book.codes.reserve(static_cast<std::size_t>(dictionary->bytesList.rows));
  for (int id = 0; id < dictionary->bytesList.rows; ++id) {
    // Rows top to bottom, 1 = white: what drawMarker prints inside the border.
    const cv::Mat bits =
        cv::aruco::Dictionary::getBitsFromByteList(dictionary->bytesList.row(id), book.bits);
    std::vector<std::uint8_t> code(static_cast<std::size_t>(book.bits) * book.bits);
    for (int r = 0; r < book.bits; ++r)
      for (int c = 0; c < book.bits; ++c)
        code[static_cast<std::size_t>(r) * book.bits + c] = bits.at<std::uint8_t>(r, c) ? 1 : 0;
    book.codes.push_back(std::move(code));
  }
  return book;
}

std::shared_ptr<const CharucoTarget> MakeCharucoTarget(const TargetSpec& spec) {
  // The dictionary first: without it the board cannot be built.
  const std::string name = spec.GetString("dictionary", "");
  if (name.empty())
    throw InputError("", "/dictionary",
                     "missing key; expected an OpenCV dictionary name such as DICT_5X5_100");
  auto target = std::make_shared<const CharucoTarget>(spec, ArucoCodebook(name));
  CharucoDetector::Options::FromSpec(spec);
  return target;
}

bool CharucoDetector::Options::Check(std::string* why) const {
  auto fail = [why](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  if (min_corners < 4) return fail("min_corners >= 4 (a pose needs four points)");
  if (!(homography_tolerance > 0 && homography_tolerance < 0.5))
    return fail("homography_tolerance in (0, 0.5) of a square");
  if (!(min_homography_tolerance_px > 0)) return fail("min_homography_tolerance_px > 0");
  return true;
}

CharucoDetector::Options CharucoDetector::Options::FromSpec(const TargetSpec& spec) {
  Options options;
  if (spec.Has("min_corners")) options.min_corners = spec.GetInt("min_corners", 4);
  return options;
}

/// OpenCV's objects for one board; read-only after construction, so Detect()
/// may run on several threads at once.
struct CharucoDetector::OpenCvState {
  cv::Ptr<cv::aruco::Dictionary> dictionary;
  cv::Ptr<cv::aruco::CharucoBoard> board;
  cv::Ptr<cv::aruco::DetectorParameters> parameters;
  /// The layouts a print may have instead of the declared one, and what to
  /// change in the target for each (internal::OtherLayouts).
  std::vector<std::pair<std::shared_ptr<const CharucoTarget>, std::string>> other_layouts;
};

CharucoDetector::CharucoDetector(std::shared_ptr<const CharucoTarget> target)
    : CharucoDetector(target, target ? internal::OptionsOfTarget<Options>(*target) : Options()) {}

CharucoDetector::CharucoDetector(std::shared_ptr<const CharucoTarget> target,
                                 const Options& options)
    : target_(std::move(target)), options_(options) {
  if (!target_) throw std::invalid_argument("CharucoDetector: null target");
  std::string why;
  if (!options_.Check(&why)) throw std::invalid_argument("CharucoDetector: expected " + why);
  auto state = std::make_unique<OpenCvState>();
  state->dictionary = PredefinedDictionary(target_->dictionary().name);
  // Board units are squares: only ratios matter to the interpolation.
  state->board = cv::aruco::CharucoBoard::create(
      target_->squares_x(), target_->squares_y(), 1.0f,
      static_cast<float>(target_->marker_size_m() / target_->square_size_m()), state->dictionary);
  // OpenCV 4.6 makes its own layout only; an older print's markers are moved.
  if (target_->legacy()) internal::LayOutMarkers(*target_, state->board.get());
  state->other_layouts = internal::OtherLayouts(*target_);
  state->parameters = cv::aruco::DetectorParameters::create();
  // Marker corners only seed the interpolation and the consistency check; the
  // chessboard corners are refined below, to X junctions.
  state->parameters->cornerRefinementMethod = cv::aruco::CORNER_REFINE_NONE;
  // Small markers, as a cell camera sees an A3 board from 2-3 m (12-20 px):
  // OpenCV's defaults found 31 % of their corners in rendered 1920x1080
  // views; these settings 88 %, with no wrong ids (the two-marker homography
  // check below rejects corners next to a misread marker).
  // - accept markers down to 1.5 % of the image's larger side in perimeter
  //   (default 3 %: 14 px markers at 1920 wide);
  state->parameters->minMarkerPerimeterRate = 0.015;
  // - read each cell from an 8×8 resampling, ignoring 30 % at its edges, so
  //   blurred neighbouring cells do not leak in (defaults 4×4, 13 %);
  state->parameters->perspectiveRemovePixelPerCell = 8;
  state->parameters->perspectiveRemoveIgnoredMarginPerCell = 0.3;
  // - correct up to 80 % of the bits the dictionary can correct (default 60 %).
  state->parameters->errorCorrectionRate = 0.8;
  cv_ = std::move(state);
}

CharucoDetector::~CharucoDetector() = default;

std::optional<Detection> CharucoDetector::Detect(const cv::Mat& gray) const {
  return Find(gray, nullptr, nullptr);
}

std::optional<Detection> CharucoDetector::Detect(const cv::Mat& gray,
                                                 std::vector<CharucoRejection>* rejected) const {
  return Find(gray, rejected, nullptr);
}

std::optional<Detection> CharucoDetector::DetectOrExplain(const cv::Mat& gray,
                                                          std::string* mismatch) const {
  return Find(gray, nullptr, mismatch);
}

std::string CharucoDetector::LayoutMismatch(
    const std::vector<int>& ids, const std::vector<std::vector<cv::Point2f>>& corners) const {
  if (ids.size() < kMinMarkersToJudgeLayout) return "";
  // The markers of a print of the declared layout fit it (but for lens
  // distortion and misreads); a print of another layout fits that one all
  // but wholly and the declared one in part (a legacy print of an even
  // number of columns: every other row of markers, one square off).
  const double declared = internal::LayoutFit(*target_, ids, corners);
  if (declared >= 0.8) return "";
  for (const auto& [layout, advice] : cv_->other_layouts) {
    const double fit = internal::LayoutFit(*layout, ids, corners);
    if (fit >= 0.8 && fit >= declared + 0.25) return advice;
  }
  return "";
}

std::variant<Eigen::Vector2d, const char*> CharucoDetector::RefineCorner(
    const cv::Mat& gray, int id, const Eigen::Matrix3d& H, const Eigen::Vector2d& guess,
    const std::vector<Eigen::Vector2d>& board_xy,
    const std::vector<Eigen::Vector2d>& image_uv) const {
  const double L = target_->square_size_m();
  const Eigen::Vector2d xy = target_->FindPoint(id)->p_target.head<2>();
  const Eigen::Vector2d predicted = internal::ApplyHomography(H, xy);
  // A square's extent in the image along its most foreshortened direction
  // (the smaller singular value of the local map): refinement windows and
  // tolerances must fit that way too.
  const auto [square_image, square_px] = SquareInImage(H, xy, L);
  if (!(square_px >= kMinSquarePx && square_px < std::max(gray.cols, gray.rows)))
    return "refinement";
  const double tolerance_px = HomographyTolerancePx(options_, square_px);
  for (std::size_t k = 0; k < board_xy.size(); ++k)
    if ((internal::ApplyHomography(H, board_xy[k]) - image_uv[k]).norm() > tolerance_px)
      return "homography";
  // The refinement window is the image of a disc of 0.6 squares around the
  // corner (capped at 30 px), so it follows the black squares' edges for
  // most of their length (the neighbouring corners' crossing edges stay a
  // square away); the two markers, grown by 2 px of blur and gradient
  // stencil, are left out, since their edges would pull the estimate. On
  // rendered 1920x1080 views with 20-40 px markers the mean corner error
  // was 0.043 px with a disc inside the marker margins, 0.020 px with 0.45
  // squares and the markers left out, 0.018 px with 0.6.
  Eigen::Matrix2d window = kWindowSquares * square_image;
  const double widest_px = Eigen::JacobiSVD<Eigen::Matrix2d>(window).singularValues()(0);
  if (widest_px > kMaxWindowPx) window *= kMaxWindowPx / widest_px;
  // The markers' outlines in the image, grown there (not on the board): seen
  // obliquely a square is a few pixels across the tilt, and 2 px taken back
  // onto the board along that direction would grow the markers over the
  // corner itself.
  std::array<std::array<Eigen::Vector2d, 4>, 2> marker_px;
  for (int k = 0; k < 2; ++k) {
    const auto corners = target_->MarkerCorners(target_->MarkersAtCorner(id)[k]);
    for (int c = 0; c < 4; ++c)
      marker_px[k][c] = internal::ApplyHomography(H, corners[c].head<2>());
  }
  const auto off_markers = [&](int x, int y) {
    const Eigen::Vector2d q(x, y);
    return DistanceOutside(marker_px[0], q) > kMarkerGuardPx &&
           DistanceOutside(marker_px[1], q) > kMarkerGuardPx;
  };
  const auto refined = internal::RefineXCorner(gray, guess, window, tolerance_px, off_markers);
  if (!refined) return "refinement";
  if ((*refined - predicted).norm() > tolerance_px) return "homography";
  return *refined;
}

void CharucoDetector::DropCornersOffTheirNeighbours(
    std::vector<std::pair<int, Eigen::Vector2d>>* found) const {
  std::map<int, Eigen::Vector2d> known(found->begin(), found->end());
  for (;;) {
    int worst = -1;
    double worst_excess = kNeighbourToleranceShare;
    for (const auto& [id, uv] : known) {
      const auto H = NeighbourHomography(*target_, known, id);
      if (!H) continue;
      const Eigen::Vector2d xy = target_->FindPoint(id)->p_target.head<2>();
      const Eigen::Vector2d predicted = internal::ApplyHomography(*H, xy);
      const double square_px = SquareInImage(*H, xy, target_->square_size_m()).second;
      const double excess = (uv - predicted).norm() / HomographyTolerancePx(options_, square_px);
      if (excess > worst_excess) worst_excess = excess, worst = id;
    }
    if (worst < 0) break;
    known.erase(worst);
  }
  found->erase(std::remove_if(found->begin(), found->end(),
                              [&](const auto& corner) { return !known.count(corner.first); }),
               found->end());
}

std::optional<Detection> CharucoDetector::Find(const cv::Mat& gray,
                                               std::vector<CharucoRejection>* rejected,
                                               std::string* mismatch) const {
  if (gray.empty() || gray.type() != CV_8UC1)
    throw std::invalid_argument("CharucoDetector: expected an 8-bit single-channel image");
  if (rejected) rejected->clear();
  if (mismatch) mismatch->clear();
  // A first stage, as for checkerboards: every inner corner of a ChArUco
  // board is an X-junction of two black squares, so a view with at least 3 x 2
  // of them holds a patch of corner grid among the saddle points, found in a
  // few ms. Without one, OpenCV's marker search (16 ms of CPU on a 1920x1080
  // image) is not run: on 40 of METRIC's images without the board 23.4 ->
  // 12.3-14.1 ms per image, decoding included; an image with the board costs
  // the stage on top (bench_detect_targets: 25.4 -> 33.9 ms). Rendered cells
  // (7 of them, 128 views, blur up to 1.5 px, noise up to 8 grey levels) and
  // bench_detect_targets gave the same views and points with it. A board of
  // 3 x 3 squares has no such block of corners: it goes without the stage.
  const int inner_x = target_->squares_x() - 1, inner_y = target_->squares_y() - 1;
  const bool has_block = std::max(inner_x, inner_y) >= 3 && std::min(inner_x, inner_y) >= 2;
  if (has_block && !internal::MayShowCornerGrid(gray, 2)) return std::nullopt;

  std::vector<std::vector<cv::Point2f>> marker_corners, candidates;
  std::vector<int> marker_ids;
  cv::aruco::detectMarkers(gray, cv_->dictionary, marker_corners, marker_ids, cv_->parameters,
                           candidates);
  // A marker id seen twice (a second board, a stray print) cannot be placed:
  // drop every copy. Ids beyond the board's markers belong to something else.
  std::map<int, int> copies;
  for (int id : marker_ids) ++copies[id];
  std::vector<std::vector<cv::Point2f>> kept_corners;
  std::vector<int> kept_ids;
  std::map<int, std::size_t> marker_index;
  for (std::size_t i = 0; i < marker_ids.size(); ++i) {
    const int id = marker_ids[i];
    if (id < 0 || id >= target_->NumMarkers() || copies[id] != 1) continue;
    marker_index[id] = kept_ids.size();
    kept_ids.push_back(id);
    kept_corners.push_back(marker_corners[i]);
  }
  // No view: say so when the markers seen fit another layout.
  auto none = [&]() -> std::optional<Detection> {
    if (mismatch) *mismatch = LayoutMismatch(kept_ids, kept_corners);
    return std::nullopt;
  };
  // Two markers interpolate the corners between them.
  std::vector<cv::Point2f> interpolated;
  std::vector<int> corner_ids;
  if (kept_ids.size() >= 2)
    cv::aruco::interpolateCornersCharuco(kept_corners, kept_ids, gray, cv_->board, interpolated,
                                         corner_ids);

  const double L = target_->square_size_m();
  std::vector<std::pair<int, Eigen::Vector2d>> found;
  auto reject = [rejected](int id, const char* reason) {
    if (rejected) rejected->push_back({id, reason});
  };
  for (std::size_t i = 0; i < corner_ids.size(); ++i) {
    const int id = corner_ids[i];
    const TargetPoint* point = target_->FindPoint(id);
    if (!point) continue;
    // The local homography of the two markers that touch this corner.
    std::vector<Eigen::Vector2d> board_xy, image_uv;
    bool both_markers = true;
    for (int marker : target_->MarkersAtCorner(id)) {
      const auto it = marker_index.find(marker);
      if (it == marker_index.end()) {
        both_markers = false;
        break;
      }
      const auto object = target_->MarkerCorners(marker);
      for (int k = 0; k < 4; ++k) {
        board_xy.push_back(object[k].head<2>());
        image_uv.push_back(ToEigen(kept_corners[it->second][k]));
      }
    }
    if (!both_markers) {
      reject(id, "homography");
      continue;
    }
    const auto H = internal::FitHomography(board_xy, image_uv);
    if (!H) {
      reject(id, "homography");
      continue;
    }
    const auto refined = RefineCorner(gray, id, *H, ToEigen(interpolated[i]), board_xy, image_uv);
    if (const auto* reason = std::get_if<const char*>(&refined)) {
      reject(id, *reason);
      continue;
    }
    found.emplace_back(id, std::get<Eigen::Vector2d>(refined));
  }

  // A corner predicted from its neighbours (no markers to check it against).
  const auto refine = [&](int id, const Eigen::Matrix3d& H, const Eigen::Vector2d& guess) {
    std::optional<Eigen::Vector2d> uv;
    if (guess.x() < 0 || guess.y() < 0 || guess.x() > gray.cols - 1 || guess.y() > gray.rows - 1)
      return uv;
    const auto refined = RefineCorner(gray, id, H, guess, {}, {});
    if (const auto* found_uv = std::get_if<Eigen::Vector2d>(&refined)) uv = *found_uv;
    return uv;
  };
  // A board seen obliquely: its far markers do not decode, but its squares'
  // corners are still there, and the markers that do decode number them.
  if (found.size() < target_->Points().size()) {
    const auto added =
        internal::GrowCharucoCorners(*target_, kept_ids, kept_corners, found, refine);
    found.insert(found.end(), added.begin(), added.end());
  }
  // Markers too small to decode at this tilt: the black squares number the
  // corners. Where too few markers decoded to tell the print's layout
  // (LayoutMismatch), the squares tell it too: a print the squares say is
  // laid out otherwise is no view of the declared board.
  {
    const auto declared =
        internal::PlaceCornersBySquares(*target_, gray, candidates, kept_ids, kept_corners);
    bool declared_leads = true;
    for (const auto& [layout, advice] : cv_->other_layouts) {
      const auto other =
          internal::PlaceCornersBySquares(*layout, gray, candidates, kept_ids, kept_corners);
      if (!other.corners.empty() && ClearlyAhead(other, declared)) {
        if (mismatch) *mismatch = advice;
        return std::nullopt;
      }
      if (!ClearlyAhead(declared, other)) declared_leads = false;
    }
    if (declared_leads && found.size() < target_->Points().size())
      AddPlacedCorners(*target_, declared.corners, refine, &found);
  }
  // A corner rejected next to the decoded markers may have been found since.
  if (rejected) {
    std::set<int> now_found;
    for (const auto& [id, uv] : found) now_found.insert(id);
    rejected->erase(
        std::remove_if(rejected->begin(), rejected->end(),
                       [&](const CharucoRejection& r) { return now_found.count(r.corner_id) > 0; }),
        rejected->end());
  }
  DropCornersOffTheirNeighbours(&found);
  // Markers of another layout can still fit one homography among themselves
  // (a row of an old-style print, shifted by a square) and number a whole
  // board a square off: the markers decoded must fit the declared layout.
  if (!LayoutMismatch(kept_ids, kept_corners).empty()) return none();
  if (static_cast<int>(found.size()) < options_.min_corners) return none();
  std::sort(found.begin(), found.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::Vector2d> on_board;
  for (const auto& [id, uv] : found) on_board.push_back(target_->FindPoint(id)->p_target.head<2>());
  // Corners on one row, column or diagonal leave the pose free to turn about it.
  if (!internal::SpansPlane(on_board, 0.5 * L)) return none();

  Detection detection;
  for (const auto& [id, uv] : found) {
    detection.ids.push_back(id);
    detection.points_px.push_back(uv);
  }
  return detection;
}

}  // namespace handeye
