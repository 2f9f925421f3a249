// SPDX-License-Identifier: GPL-2.0-or-later
#include "aprilgrid_alignment.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>
#include <opencv2/video/tracking.hpp>

#include "corner_refinement.h"

namespace handeye::internal {
namespace {

/// Supersamples per template pixel side when rendering the print.
constexpr int kSupersampling = 4;
/// Pixels of image kept around the grid for the alignment.
constexpr int kCropMarginPx = 16;
/// Outlines tried as the sheet's when no tag decodes, and the size of
/// its tags they imply (the side of a square of the sheet's area ÷ its
/// tags, px): beyond it the tags would decode.
constexpr std::size_t kMaxOutlines = 12;
constexpr double kMinOutlineTagPx = 6, kMaxOutlineTagPx = 32;
/// The bright regions: above their neighbourhood's mean by this much.
constexpr int kThresholdBlockPx = 31, kThresholdOffset = 5;
/// The pieces of a sheet whose outline is lost: their area (px²), how far
/// apart they may lie, and how many make a sheet (JoinedPieces).
constexpr double kMinPieceAreaPx = 60, kMaxPieceAreaPx = 3000;
constexpr int kPieceReachPx = 3, kMinPieces = 3;
/// How far (÷ its side) a decoded tag's corner may lie from where an
/// alignment from the seeds puts it, and how far from where an outline's
/// alignment puts it before the tag contradicts it. The corners the library
/// gives a tag too small to fit are rough: on a rendered view at 64° an
/// outline's alignment (data cells correlating 0.62 with the print, 0.06 for
/// any other) was refused for its one decoded tag's corners, a tenth of the
/// side off; a tag placed elsewhere is off by a whole side.
constexpr double kSeedTolerance = 0.1, kSeedContradiction = 0.5;
/// What an outline must hold to be tried (LooksLikeGrid): the sheet's, and
/// the dark network's inside its margin (on rendered oblique views 59-83 %
/// of its pixels not bright, at a grey-level σ of 37-51; dark clutter, 80-100
/// % and σ 3-15 mostly, falls under the σ bound).
constexpr double kMinDarkFraction = 0.3, kMaxDarkFraction = 0.65, kMinGreySigma = 15;
constexpr double kMinInsideDarkFraction = 0.4, kMaxInsideDarkFraction = 0.9;
/// The white margin around the dark network: a band this wide just outside
/// its outline, this share of it bright (MarginAround). On a white surface
/// the bands of the networks were 94-98 % bright; of the 76 dark outlines
/// that looked like a grid in a rendered cell's 96 images, 70 under 70 %.
constexpr int kMarginBandPx = 2;
constexpr double kMinMarginBright = 0.7;
/// The short, smoothed alignment of every outline's turns, and the
/// correlation after it for a turn to be aligned in full: the sheet's
/// outline, and the dark network's inside the margin (on rendered views at
/// 60-75 degrees the turns that then lined up at 0.4 or more had reached
/// 0.42-0.75 coarsely, 9 of the 12 others under 0.11; one full alignment of
/// a wrong outline cost a METRIC image with no grid 0.27 s).
constexpr int kCoarseIterations = 10;
constexpr double kMinCoarseCorrelation = 0.05, kMinInsideCoarseCorrelation = 0.2;
/// How much larger than an outline the sheet it implies may be (AlignFromOutlines).
constexpr double kMaxSheetToOutline = 2.0;
/// The blurs tried for the image (Predict), px.
constexpr double kMinBlurPx = 0.2, kMaxBlurPx = 2.6, kBlurStepPx = 0.3;
/// The alignment of a tag's neighbourhood (LocalCorners): its iterations,
/// the least pixels it needs, and how far (÷ the tag's side) it may move
/// the tag from where the sheet's H puts it.
constexpr int kLocalIterations = 30, kMinLocalPixels = 40;
constexpr double kMaxLocalShift = 0.1;

/// The print rendered about as large as it appears: template pixel (u, v)
/// shows board point (x0 + u / s, y0 − v / s), x0, y0 the top-left of
/// the sheet (Target::Extent).
struct Template {
  cv::Mat image;                      ///< CV_8U
  Eigen::Matrix3d S_template_target;  ///< board metres → template pixels
};

Template RenderTemplate(const AprilGridTarget& target, double px_per_m) {
  const Eigen::AlignedBox2d e = target.Extent();
  const double s = px_per_m;
  Template t;
  t.S_template_target << s, 0, -s * e.min().x(), 0, -s, s * e.max().y(), 0, 0, 1;
  const int w = static_cast<int>(std::ceil(s * e.sizes().x())),
            h = static_cast<int>(std::ceil(s * e.sizes().y()));
  t.image.create(h, w, CV_8U);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      double sum = 0;
      for (int a = 0; a < kSupersampling; ++a)
        for (int b = 0; b < kSupersampling; ++b) {
          const double du = (a + 0.5) / kSupersampling - 0.5, dv = (b + 0.5) / kSupersampling - 0.5;
          sum += target.Albedo(e.min().x() + (u + du) / s, e.max().y() - (v + dv) / s);
        }
      t.image.at<std::uint8_t>(v, u) =
          cv::saturate_cast<std::uint8_t>(255.0 * sum / (kSupersampling * kSupersampling));
    }
  return t;
}

/// The box in the image around the corners of `part` of the board under H.
Eigen::AlignedBox2d ImageBox(const Eigen::Matrix3d& H, const Eigen::AlignedBox2d& part) {
  Eigen::AlignedBox2d seen;
  for (const auto corner : {Eigen::AlignedBox2d::BottomLeft, Eigen::AlignedBox2d::BottomRight,
                            Eigen::AlignedBox2d::TopLeft, Eigen::AlignedBox2d::TopRight})
    seen.extend(ApplyHomography(H, part.corner(corner)));
  return seen;
}

/// The print rendered for the part of `gray` the sheet covers under H, and that part.
struct Frame {
  Template print;
  cv::Rect crop;
};

std::optional<Frame> FrameFor(const cv::Mat& gray, const AprilGridTarget& target,
                              const Eigen::Matrix3d& H) {
  const Eigen::AlignedBox2d e = target.Extent();
  const Eigen::AlignedBox2d seen = ImageBox(H, e);
  if (!seen.sizes().allFinite() || seen.sizes().maxCoeff() > 4.0 * (gray.cols + gray.rows))
    return std::nullopt;
  Frame frame;
  frame.crop = cv::Rect(static_cast<int>(std::floor(seen.min().x())) - kCropMarginPx,
                        static_cast<int>(std::floor(seen.min().y())) - kCropMarginPx,
                        static_cast<int>(std::ceil(seen.sizes().x())) + 2 * kCropMarginPx,
                        static_cast<int>(std::ceil(seen.sizes().y())) + 2 * kCropMarginPx) &
               cv::Rect(0, 0, gray.cols, gray.rows);
  if (frame.crop.width < 8 || frame.crop.height < 8) return std::nullopt;
  // About one template pixel per image pixel along the sheet's longer side.
  const double longest = std::max(seen.sizes().x(), seen.sizes().y());
  frame.print = RenderTemplate(target, std::max(longest, 64.0) / e.sizes().maxCoeff());
  return frame;
}

/// H (board → pixels) refined by ECC of the frame's print against its part
/// of `gray`, both smoothed by a Gaussian of `smoothing` px (1: none).
std::optional<Eigen::Matrix3d> Align(const cv::Mat& gray, const Frame& frame,
                                     const Eigen::Matrix3d& H, int smoothing, int iterations) {
  Eigen::Matrix3d shift = Eigen::Matrix3d::Identity();
  shift(0, 2) = -frame.crop.x;
  shift(1, 2) = -frame.crop.y;
  Eigen::Matrix3d W = shift * H * frame.print.S_template_target.inverse();
  W /= W(2, 2);
  cv::Mat warp(3, 3, CV_32F);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) warp.at<float>(r, c) = static_cast<float>(W(r, c));
  try {
    cv::findTransformECC(
        frame.print.image, gray(frame.crop), warp, cv::MOTION_HOMOGRAPHY,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, iterations, 1e-5),
        cv::noArray(), smoothing);
  } catch (const cv::Exception&) {
    return std::nullopt;  // did not converge
  }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) W(r, c) = warp.at<float>(r, c);
  const Eigen::Matrix3d aligned = shift.inverse() * W * frame.print.S_template_target;
  if (!aligned.allFinite()) return std::nullopt;
  return aligned;
}

/// Appends the image's grey levels and the print's at the centres of tag
/// `tag`'s cells [lo, hi)² under H (cells count from the tag's top-left in
/// bits; −1 and n are the gap around a tag of n bits). False, appending
/// nothing, when a cell falls outside the image.
bool SampleTag(const AprilGridTarget& target, const cv::Mat& gray, const Eigen::Matrix3d& H,
               int tag, int lo, int hi, std::vector<double>* seen, std::vector<double>* printed) {
  const int n = target.family().bits + 2 * target.border_bits();
  const double size = target.tag_size_m(), pitch = size * (1 + target.tag_spacing()),
               bit = size / n;
  const int i = tag % target.tags_x(), j = tag / target.tags_x();
  std::vector<Eigen::Vector2d> cells, pixels;
  for (int r = lo; r < hi; ++r)
    for (int c = lo; c < hi; ++c) {
      // Tag (i, j) spans x in [i·p, i·p + size], y in [−j·p − size, −j·p].
      const Eigen::Vector2d xy(i * pitch + (c + 0.5) * bit, -j * pitch - size + (r + 0.5) * bit);
      const Eigen::Vector2d uv = ApplyHomography(H, xy);
      if (!(uv.x() >= 0 && uv.y() >= 0 && uv.x() < gray.cols - 1 && uv.y() < gray.rows - 1))
        return false;
      cells.push_back(xy);
      pixels.push_back(uv);
    }
  for (std::size_t k = 0; k < cells.size(); ++k) {
    seen->push_back(Bilinear(gray, pixels[k].x(), pixels[k].y()));
    printed->push_back(target.Albedo(cells[k].x(), cells[k].y()));
  }
  return true;
}

/// Whether tag `tag` is seen where H puts it: the grey levels of its cells
/// and the gap around them follow the print (its black border against the
/// white gap stays clear when the data cells blur together), and so do
/// those of its own cells alone (something in front of the tag, with the
/// gap around it in view, fails this). nullopt when the tag and its gap are
/// not all in the image.
std::optional<bool> TagSeen(const AprilGridTarget& target, const cv::Mat& gray,
                            const Eigen::Matrix3d& H, int tag) {
  const int n = target.family().bits + 2 * target.border_bits();
  std::vector<double> seen, printed;
  if (!SampleTag(target, gray, H, tag, -1, n + 1, &seen, &printed)) return std::nullopt;
  const auto with_gap = Pearson(seen, printed);
  seen.clear();
  printed.clear();
  SampleTag(target, gray, H, tag, 0, n, &seen, &printed);
  const auto own = Pearson(seen, printed);
  return with_gap && own && *with_gap >= kMinTagCorrelation && *own >= kMinOwnCorrelation;
}

/// Correlation of the image at the data cells of every tag in the image
/// under H with the print: what tells the grid's placements apart, as the
/// borders and gaps fit every turn alike. nullopt with fewer than two tags
/// in the image.
std::optional<double> GridCorrelation(const AprilGridTarget& target, const cv::Mat& gray,
                                      const Eigen::Matrix3d& H) {
  const int n = target.family().bits + 2 * target.border_bits(), b = target.border_bits();
  std::vector<double> seen, printed;
  int tags = 0;
  for (int tag = 0; tag < target.NumTags(); ++tag)
    tags += SampleTag(target, gray, H, tag, b, n - b, &seen, &printed);
  if (tags < 2) return std::nullopt;
  return Pearson(seen, printed);
}

/// `quad` (image pixels) filled into a mask of `box` (CV_8U, 255 inside).
cv::Mat QuadMask(const std::vector<cv::Point>& quad, const cv::Rect& box) {
  cv::Mat mask = cv::Mat::zeros(box.size(), CV_8U);
  std::vector<cv::Point> local;
  for (const cv::Point& corner : quad) local.push_back(corner - box.tl());
  cv::fillConvexPoly(mask, local, 255);
  return mask;
}

/// Whether the inside of `quad` could be an AprilGrid: part bright, part
/// dark (`bright`: the thresholded image), and not flat. On rendered oblique
/// views the sheets' outlines held 40-53 % dark pixels at a grey-level σ of
/// 36-66; 37 of the 48 outlines in 40 of METRIC's images (no grid in them)
/// fall outside the bounds below.
bool LooksLikeGrid(const cv::Mat& gray, const cv::Mat& bright, const std::vector<cv::Point>& quad,
                   double min_dark, double max_dark) {
  const cv::Rect box = cv::boundingRect(quad) & cv::Rect(0, 0, gray.cols, gray.rows);
  if (box.empty()) return false;
  const cv::Mat inside = QuadMask(quad, box);
  const int pixels = cv::countNonZero(inside);
  if (pixels == 0) return false;
  const double dark = static_cast<double>(cv::countNonZero((bright(box) == 0) & inside)) / pixels;
  cv::Scalar mean, sigma;
  cv::meanStdDev(gray(box), mean, sigma, inside);
  return dark >= min_dark && dark <= max_dark && sigma[0] >= kMinGreySigma;
}

/// Whether the band kMarginBandPx wide just outside `quad` is mostly bright
/// (`bright`: the image's bright regions), as the white margin around the
/// tags is.
bool MarginAround(const cv::Mat& bright, const std::vector<cv::Point>& quad) {
  const int reach = kMarginBandPx + 1;
  const cv::Rect box = cv::Rect(cv::boundingRect(quad).tl() - cv::Point(reach, reach),
                                cv::boundingRect(quad).br() + cv::Point(reach, reach)) &
                       cv::Rect(0, 0, bright.cols, bright.rows);
  if (box.empty()) return false;
  const cv::Mat inside = QuadMask(quad, box);
  cv::Mat grown;
  cv::dilate(inside, grown,
             cv::getStructuringElement(cv::MORPH_ELLIPSE,
                                       cv::Size(2 * kMarginBandPx + 1, 2 * kMarginBandPx + 1)));
  const cv::Mat band = grown & ~inside;
  const int pixels = cv::countNonZero(band);
  return pixels > 0 && cv::countNonZero(band & bright(box)) >= kMinMarginBright * pixels;
}

double ContourHullArea(const std::vector<cv::Point>& contour) {
  std::vector<cv::Point> hull;
  cv::convexHull(contour, hull);
  return cv::contourArea(hull);
}

/// Small bright regions whose boxes, grown by kPieceReachPx, overlap,
/// joined (at least kMinPieces each).
std::vector<std::vector<cv::Point>> JoinedPieces(
    const std::vector<std::vector<cv::Point>>& contours) {
  std::vector<const std::vector<cv::Point>*> pieces;
  std::vector<cv::Rect> reach;
  for (const auto& contour : contours) {
    const double area = cv::contourArea(contour);
    if (area < kMinPieceAreaPx || area > kMaxPieceAreaPx) continue;
    pieces.push_back(&contour);
    const cv::Rect box = cv::boundingRect(contour);
    reach.emplace_back(box.x - kPieceReachPx, box.y - kPieceReachPx, box.width + 2 * kPieceReachPx,
                       box.height + 2 * kPieceReachPx);
  }
  std::vector<std::size_t> group(pieces.size());
  for (std::size_t i = 0; i < group.size(); ++i) group[i] = i;
  const auto root = [&group](std::size_t i) {
    while (group[i] != i) i = group[i] = group[group[i]];
    return i;
  };
  for (std::size_t i = 0; i < pieces.size(); ++i)
    for (std::size_t j = i + 1; j < pieces.size(); ++j)
      if ((reach[i] & reach[j]).area() > 0) group[root(i)] = root(j);
  std::map<std::size_t, std::vector<cv::Point>> joined;
  std::map<std::size_t, int> count;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    auto& points = joined[root(i)];
    points.insert(points.end(), pieces[i]->begin(), pieces[i]->end());
    ++count[root(i)];
  }
  std::vector<std::vector<cv::Point>> out;
  for (auto& [r, points] : joined)
    if (count[r] >= kMinPieces) out.push_back(std::move(points));
  return out;
}

/// The part of the print inside its white margin: the tags and the black
/// squares between them (see AprilGridTarget::Albedo), which blur into one
/// dark network when the gaps are thin.
Eigen::AlignedBox2d DarkPart(const AprilGridTarget& target) {
  const Eigen::AlignedBox2d e = target.Extent();
  const double gap_m = target.tag_spacing() * target.tag_size_m();
  return Eigen::AlignedBox2d(e.min() + Eigen::Vector2d::Constant(gap_m),
                             e.max() - Eigen::Vector2d::Constant(gap_m));
}

/// A quadrilateral in the image (clockwise) that may outline `part` of the sheet.
struct Outline {
  std::array<Eigen::Vector2d, 4> corners;
  Eigen::AlignedBox2d part;
};

/// Quadrilaterals that may outline `part` of the sheet, largest first: the
/// hulls of `contours` (each filling its hull at least half) and of pieces
/// of them joined (JoinedPieces) that are quadrilaterals of an area that suits a grid of
/// tags too small to decode, and look like a grid inside (`bright`: the
/// image's bright regions), with a bright `margin` around them if asked.
std::vector<Outline> QuadOutlines(const cv::Mat& gray, const cv::Mat& bright,
                                  const AprilGridTarget& target, const Eigen::AlignedBox2d& part,
                                  double min_dark, double max_dark, bool margin,
                                  const std::vector<std::vector<cv::Point>>& contours) {
  const double tags_in_part = part.sizes().prod() / (target.tag_size_m() * target.tag_size_m());
  std::vector<std::pair<double, Outline>> found;
  const auto consider = [&](const std::vector<cv::Point>& region) {
    std::vector<cv::Point> hull, quad;
    cv::convexHull(region, hull);
    const double area = cv::contourArea(hull);
    const double tag_px = std::sqrt(area / tags_in_part);
    if (tag_px < kMinOutlineTagPx || tag_px > kMaxOutlineTagPx) return;
    cv::approxPolyDP(hull, quad, 0.03 * cv::arcLength(hull, true), true);
    if (quad.size() != 4 || !LooksLikeGrid(gray, bright, quad, min_dark, max_dark)) return;
    if (margin && !MarginAround(bright, quad)) return;
    Outline outline;
    outline.part = part;
    for (int k = 0; k < 4; ++k) outline.corners[k] = Eigen::Vector2d(quad[k].x, quad[k].y);
    found.emplace_back(area, outline);
  };
  for (const auto& contour : contours)
    if (cv::contourArea(contour) >= 0.5 * ContourHullArea(contour)) consider(contour);
  // The part in pieces: for the sheet, its margin lost across the tilt or
  // joined to something bright behind it, the gaps between its tags, each a
  // bright strip; inside the margin, tags apart.
  for (const std::vector<cv::Point>& pieces : JoinedPieces(contours)) consider(pieces);
  std::sort(found.begin(), found.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Outline> outlines;
  for (std::size_t k = 0; k < found.size() && k < kMaxOutlines; ++k)
    outlines.push_back(found[k].second);
  return outlines;
}

/// Outlines of the whole sheet: bright regions (its white margin and gaps,
/// against what is behind it). Every contour, holes included: the sheet is
/// often a hole in what is behind it.
std::vector<Outline> SheetOutlines(const cv::Mat& gray, const cv::Mat& bright,
                                   const AprilGridTarget& target) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(bright, contours, cv::RETR_LIST, cv::CHAIN_APPROX_SIMPLE);
  return QuadOutlines(gray, bright, target, target.Extent(), kMinDarkFraction, kMaxDarkFraction,
                      false, contours);
}

/// Outlines of the part inside the margin: dark regions (the tags and the
/// squares between them), for a sheet whose margin joins something bright
/// behind it, so that it has no bright outline.
std::vector<Outline> InsideOutlines(const cv::Mat& gray, const cv::Mat& bright,
                                    const AprilGridTarget& target) {
  cv::Mat dark;
  cv::adaptiveThreshold(gray, dark, 255, cv::ADAPTIVE_THRESH_MEAN_C, cv::THRESH_BINARY_INV,
                        kThresholdBlockPx, kThresholdOffset);
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(dark, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  return QuadOutlines(gray, bright, target, DarkPart(target), kMinInsideDarkFraction,
                      kMaxInsideDarkFraction, true, contours);
}

/// How many of the decoded tags have a corner more than `fraction` of their
/// side from where H puts it.
int SeedsOff(const AprilGridTarget& target, const std::vector<SeedTag>& seeds,
             const Eigen::Matrix3d& H, double fraction) {
  int off = 0;
  for (const SeedTag& seed : seeds) {
    const auto ids = target.TagCornerIds(seed.tag);
    const double side = (seed.corners_px[1] - seed.corners_px[0]).norm();
    bool moved = false;
    for (int k = 0; k < 4; ++k)
      moved |=
          (ApplyHomography(H, target.FindPoint(ids[k])->p_target.head<2>()) - seed.corners_px[k])
              .norm() > fraction * side;
    off += moved;
  }
  return off;
}

/// The homography of the decoded tags, aligned; nullopt when a seed's
/// corners end more than a tenth of its side from where the alignment puts
/// them.
std::optional<Eigen::Matrix3d> AlignFromSeeds(const AprilGridTarget& target, const cv::Mat& gray,
                                              const std::vector<SeedTag>& seeds) {
  std::vector<Eigen::Vector2d> on_board, in_image;
  for (const SeedTag& seed : seeds) {
    const auto ids = target.TagCornerIds(seed.tag);
    for (int k = 0; k < 4; ++k) {
      on_board.push_back(target.FindPoint(ids[k])->p_target.head<2>());
      in_image.push_back(seed.corners_px[k]);
    }
  }
  const auto start = FitHomography(on_board, in_image);
  if (!start) return std::nullopt;
  const auto frame = FrameFor(gray, target, *start);
  if (!frame) return std::nullopt;
  // Smoothed first (a wider basin), then at full detail.
  auto H = Align(gray, *frame, *start, 5, 50);
  if (H) H = Align(gray, *frame, *H, 1, 50);
  if (!H) return std::nullopt;
  if (SeedsOff(target, seeds, *H, kSeedTolerance) > 0) return std::nullopt;
  return H;
}

/// With no tag decoded: each outline in each of its four turns, aligned
/// coarsely, and in full in the `fine_turns` turns that line up best at
/// `min_coarse` or more; the alignment under which the data cells follow the
/// print clearly best.
std::optional<Eigen::Matrix3d> AlignFromOutlines(const AprilGridTarget& target, const cv::Mat& gray,
                                                 const std::vector<Outline>& outlines,
                                                 int fine_turns, double min_coarse) {
  const auto corners = [](const Eigen::AlignedBox2d& e) {
    return std::vector<Eigen::Vector2d>{
        Eigen::Vector2d(e.min().x(), e.max().y()), Eigen::Vector2d(e.max().x(), e.max().y()),
        Eigen::Vector2d(e.max().x(), e.min().y()), Eigen::Vector2d(e.min().x(), e.min().y())};
  };
  const std::vector<Eigen::Vector2d> sheet = corners(target.Extent());
  std::vector<std::pair<double, Eigen::Matrix3d>> aligned;
  for (const Outline& outline : outlines) {
    Eigen::AlignedBox2d outline_box;
    for (const Eigen::Vector2d& corner : outline.corners) outline_box.extend(corner);
    std::optional<Frame> frame;
    // A short smoothed alignment sorts the turns; the fine one is for the
    // likely ones only, the `fine_turns` most likely.
    std::vector<std::pair<double, Eigen::Matrix3d>> likely;
    // The outline runs clockwise in the image; the part's corners, seen from
    // its printed side, the other way.
    const std::vector<Eigen::Vector2d> from = corners(outline.part);
    for (int turn = 0; turn < 4; ++turn) {
      std::vector<Eigen::Vector2d> to;
      for (int k = 0; k < 4; ++k) to.push_back(outline.corners[(turn + 4 - k) % 4]);
      const auto start = FitHomography(from, to);
      if (!start) continue;
      // An outline of part of the sheet places the rest by extrapolation: a
      // skewed one puts the sheet far beyond it (a 345 x 846 px frame from a
      // 60 px outline of clutter, 0.4 s a coarse alignment). The sheet may
      // be at most twice the outline's size.
      const Eigen::AlignedBox2d sheet_box = ImageBox(*start, target.Extent());
      if (!(sheet_box.sizes().array() <= kMaxSheetToOutline * outline_box.sizes().array()).all())
        continue;
      if (!frame) frame = FrameFor(gray, target, *start);
      if (!frame) break;
      const auto H = Align(gray, *frame, *start, 5, kCoarseIterations);
      const auto coarse = H ? GridCorrelation(target, gray, *H) : std::nullopt;
      if (coarse && *coarse >= min_coarse) likely.emplace_back(*coarse, *H);
    }
    std::stable_sort(likely.begin(), likely.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    if (likely.size() > static_cast<std::size_t>(fine_turns)) likely.resize(fine_turns);
    for (const auto& [coarse, start] : likely) {
      auto H = Align(gray, *frame, start, 5, 50);
      if (H) H = Align(gray, *frame, *H, 1, 50);
      if (!H) continue;
      if (const auto score = GridCorrelation(target, gray, *H)) aligned.emplace_back(*score, *H);
    }
  }
  if (aligned.empty()) return std::nullopt;
  std::sort(aligned.begin(), aligned.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  const Eigen::Matrix3d& best = aligned.front().second;
  // The same alignment reached from another outline or turn is no rival.
  const auto same = [&](const Eigen::Matrix3d& H) {
    for (const Eigen::Vector2d& corner : sheet)
      if ((ApplyHomography(H, corner) - ApplyHomography(best, corner)).norm() > 2.0) return false;
    return true;
  };
  double runner_up = -1;
  for (std::size_t k = 1; k < aligned.size() && runner_up < 0; ++k)
    if (!same(aligned[k].second)) runner_up = std::max(aligned[k].first, 0.0);
  if (aligned.front().first < kMinGridCorrelation ||
      aligned.front().first - runner_up < kMinGridLead)
    return std::nullopt;
  return best;
}

/// The image as the sheet's H predicts it on the pixels of `box` (CV_32F),
/// and the pixels wholly on the sheet.
struct Prediction {
  cv::Rect box;
  cv::Mat image;
  cv::Mat on_sheet;  ///< CV_8U, 255 on the sheet
};

/// The print rendered under H over the part of `gray` the sheet covers, with
/// the Gaussian blur (σ, px) under which it correlates best with the image.
/// The blur matters: a sharp print lined up with a blurred image by
/// correlation over a window is pulled off where the window cuts through the
/// pattern; on rendered oblique views (blur σ 0.6-1.2 px) the corners of a
/// view so placed drew together, the sheet 1.3e-4 (median) and up to 1e-3
/// smaller than it was, which moved cameras away by half a millimetre.
/// With the blur matched the median was 0.25e-4 (too little blur: the same
/// sign; too much: the other).
std::optional<Prediction> Predict(const AprilGridTarget& target, const cv::Mat& gray,
                                  const Eigen::Matrix3d& H) {
  const Eigen::AlignedBox2d e = target.Extent();
  const Eigen::AlignedBox2d seen = ImageBox(H, e);
  if (!seen.sizes().allFinite() || seen.sizes().maxCoeff() > gray.cols + gray.rows)
    return std::nullopt;
  Prediction p;
  p.box = cv::Rect(static_cast<int>(std::floor(seen.min().x())) - 1,
                   static_cast<int>(std::floor(seen.min().y())) - 1,
                   static_cast<int>(std::ceil(seen.sizes().x())) + 3,
                   static_cast<int>(std::ceil(seen.sizes().y())) + 3) &
          cv::Rect(0, 0, gray.cols, gray.rows);
  if (p.box.width < 8 || p.box.height < 8) return std::nullopt;
  // For the blur: away from the sheet's outline by half a gap, as what lies
  // beyond it is blurred into its margin.
  const double g = 0.5 * target.tag_size_m() * target.tag_spacing();
  const Eigen::AlignedBox2d inner(e.min() + Eigen::Vector2d(g, g), e.max() - Eigen::Vector2d(g, g));
  const Eigen::Matrix3d H_target_image = H.inverse();
  cv::Mat sharp(p.box.size(), CV_32F), inside(p.box.size(), CV_8U);
  cv::Mat print_in(p.box.size(), CV_32F), cover(p.box.size(), CV_32F);
  for (int y = 0; y < p.box.height; ++y)
    for (int x = 0; x < p.box.width; ++x) {
      double sum = 0, sum_in = 0;
      int n_in = 0;
      for (int a = 0; a < kSupersampling; ++a)
        for (int b = 0; b < kSupersampling; ++b) {
          const Eigen::Vector2d uv(p.box.x + x + (a + 0.5) / kSupersampling - 0.5,
                                   p.box.y + y + (b + 0.5) / kSupersampling - 0.5);
          const Eigen::Vector2d xy = ApplyHomography(H_target_image, uv);
          const double albedo = target.Albedo(xy.x(), xy.y());
          sum += albedo;
          if (e.contains(xy)) {
            sum_in += albedo;
            ++n_in;
          }
        }
      const double n = kSupersampling * kSupersampling;
      print_in.at<float>(y, x) = static_cast<float>(255.0 * sum_in / n);
      cover.at<float>(y, x) = static_cast<float>(n_in / n);
      sharp.at<float>(y, x) = static_cast<float>(255.0 * sum / (kSupersampling * kSupersampling));
      const Eigen::Vector2d xy =
          ApplyHomography(H_target_image, Eigen::Vector2d(p.box.x + x, p.box.y + y));
      inside.at<std::uint8_t>(y, x) = inner.contains(xy) ? 255 : 0;
    }
  cv::Mat seen_px;
  gray(p.box).convertTo(seen_px, CV_32F);
  // Blurred by σ: the print, and the pixels whose blur reaches no further
  // than the sheet (nor the box's border).
  const auto blurred = [&](double sigma, cv::Mat* image, cv::Mat* valid) {
    cv::GaussianBlur(sharp, *image, cv::Size(0, 0), sigma, sigma, cv::BORDER_REPLICATE);
    const int r = static_cast<int>(std::ceil(2.0 * sigma));
    cv::Mat framed = inside.clone();
    cv::rectangle(framed, cv::Rect(0, 0, framed.cols, framed.rows), cv::Scalar(0), 1);
    cv::erode(framed, *valid, cv::Mat::ones(2 * r + 1, 2 * r + 1, CV_8U));
  };
  const auto correlation = [&](double sigma) {
    cv::Mat image, valid;
    blurred(sigma, &image, &valid);
    std::vector<double> a, b;
    for (int y = 0; y < image.rows; ++y)
      for (int x = 0; x < image.cols; ++x)
        if (valid.at<std::uint8_t>(y, x)) {
          a.push_back(image.at<float>(y, x));
          b.push_back(seen_px.at<float>(y, x));
        }
    return Pearson(a, b).value_or(-1.0);
  };
  // The best of a coarse ladder, then the vertex of the parabola through it
  // and its neighbours.
  std::vector<double> score;
  for (double sigma = kMinBlurPx; sigma <= kMaxBlurPx + 1e-9; sigma += kBlurStepPx)
    score.push_back(correlation(sigma));
  const std::size_t best =
      static_cast<std::size_t>(std::max_element(score.begin(), score.end()) - score.begin());
  double blur_px = kMinBlurPx + kBlurStepPx * static_cast<double>(best);
  if (best > 0 && best + 1 < score.size()) {
    const double l = score[best - 1], c = score[best], r = score[best + 1];
    const double curvature = l - 2 * c + r;
    if (curvature < 0) blur_px += 0.5 * kBlurStepPx * (l - r) / curvature;
  }
  // The prediction up to the sheet's edge: the print in the image's grey
  // levels (gain and offset from the sheet's inside under that blur), and
  // what lies behind the sheet as the image shows it, filled in from further
  // out where the sheet's own blur reaches; all blurred. Cut off a blur's
  // reach inside the sheet instead, the windows of the tags at its ends were
  // lopsided: on a rendered view at 70° the tags at the far end along the
  // tilt were pulled inwards by 0.10-0.13 px, and the solve read two such
  // views as a principal point 1.3 px off. The least scale of a view's
  // corners against the truth, per capture of bench/aprilgrid-oblique (seeds
  // 1, 2, 3, 5): −4.6e-4 to −11.9e-4 before, −0.9e-4 to −3.9e-4 with the
  // edge modelled (seed 4: −4.4e-4; the old detector's −0.7e-4 to −9.9e-4).
  cv::Mat print, interior;
  blurred(blur_px, &print, &interior);
  double sa = 0, sb = 0, saa = 0, sab = 0;
  int n = 0;
  for (int y = 0; y < print.rows; ++y)
    for (int x = 0; x < print.cols; ++x)
      if (interior.at<std::uint8_t>(y, x)) {
        const double a = print.at<float>(y, x), b = seen_px.at<float>(y, x);
        sa += a;
        sb += b;
        saa += a * a;
        sab += a * b;
        ++n;
      }
  if (n < 2 || !(n * saa - sa * sa > 0)) return std::nullopt;
  const double gain = (n * sab - sa * sb) / (n * saa - sa * sa), offset = (sb - gain * sa) / n;
  const int reach = static_cast<int>(std::ceil(2.0 * blur_px)) + 1;
  cv::Mat halo, behind_grey, behind;
  cv::dilate(cover > 0.0f, halo, cv::Mat::ones(2 * reach + 1, 2 * reach + 1, CV_8U));
  cv::inpaint(gray(p.box), halo, behind_grey, reach, cv::INPAINT_TELEA);
  behind_grey.convertTo(behind, CV_32F);
  cv::Mat composite = gain * print_in + offset * cover + behind.mul(1.0 - cover);
  cv::GaussianBlur(composite, p.image, cv::Size(0, 0), blur_px, blur_px, cv::BORDER_REPLICATE);
  // Wholly on the sheet, and not where the blur reaches past the box's border.
  cv::Mat framed = cv::Mat::zeros(p.box.size(), CV_8U);
  if (p.box.width > 2 * reach && p.box.height > 2 * reach)
    framed(cv::Rect(reach, reach, p.box.width - 2 * reach, p.box.height - 2 * reach)).setTo(255);
  p.on_sheet = (cover >= 1.0f) & framed;
  return p;
}

/// Tag `tag`'s corners (TagCornerIds() order) under the sheet's H, shifted
/// by where the image around the tag lines up best with the prediction
/// there. The one homography of the whole sheet is least sure of its
/// perspective across the tilt: on rendered oblique views its corners lay
/// off by up to 0.4 px, every corner of a view in one smooth pattern, which
/// the solve, trusting corners to 0.05 px, took for the pose. A shift alone,
/// from the tag and its neighbours, is well determined where a homography
/// of that patch is not. nullopt when the tag's neighbourhood is not all in
/// the prediction, the alignment fails, or the shift exceeds kMaxLocalShift
/// of the tag's side.
std::optional<std::array<Eigen::Vector2d, 4>> LocalCorners(const AprilGridTarget& target,
                                                           const cv::Mat& gray,
                                                           const Eigen::Matrix3d& H,
                                                           const Prediction& prediction, int tag) {
  const double size = target.tag_size_m(), gap = size * target.tag_spacing(), pitch = size + gap;
  const int i = tag % target.tags_x(), j = tag / target.tags_x();
  // The tag with half of each neighbour and the gaps between; tag (i, j)
  // spans x in [i·p, i·p + size], y in [−j·p − size, −j·p].
  const double reach = 0.5 * pitch + gap;
  const Eigen::AlignedBox2d part(Eigen::Vector2d(i * pitch - reach, -j * pitch - size - reach),
                                 Eigen::Vector2d(i * pitch + size + reach, -j * pitch + reach));
  const Eigen::AlignedBox2d seen = ImageBox(H, part);
  const cv::Rect crop = cv::Rect(static_cast<int>(std::floor(seen.min().x())),
                                 static_cast<int>(std::floor(seen.min().y())),
                                 static_cast<int>(std::ceil(seen.sizes().x())) + 2,
                                 static_cast<int>(std::ceil(seen.sizes().y())) + 2) &
                        prediction.box;
  if (crop.width < 4 || crop.height < 4) return std::nullopt;
  const cv::Rect local = crop - prediction.box.tl();
  const Eigen::Matrix3d H_target_image = H.inverse();
  cv::Mat mask = prediction.on_sheet(local).clone();
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x) {
      const Eigen::Vector2d xy =
          ApplyHomography(H_target_image, Eigen::Vector2d(crop.x + x, crop.y + y));
      if (!part.contains(xy)) mask.at<std::uint8_t>(y, x) = 0;
    }
  if (cv::countNonZero(mask) < kMinLocalPixels) return std::nullopt;
  cv::Mat seen_px;
  gray(crop).convertTo(seen_px, CV_32F);
  cv::Mat warp = cv::Mat::eye(2, 3, CV_32F);
  try {
    cv::findTransformECC(
        prediction.image(local), seen_px, warp, cv::MOTION_TRANSLATION,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, kLocalIterations, 1e-6),
        mask, 1);
  } catch (const cv::Exception&) {
    return std::nullopt;  // did not converge
  }
  const Eigen::Vector2d shift(warp.at<float>(0, 2), warp.at<float>(1, 2));
  const auto ids = target.TagCornerIds(tag);
  std::array<Eigen::Vector2d, 4> corners;
  for (int k = 0; k < 4; ++k)
    corners[k] = ApplyHomography(H, target.FindPoint(ids[k])->p_target.head<2>()) + shift;
  const double side = std::min((corners[1] - corners[0]).norm(), (corners[3] - corners[0]).norm());
  if (!shift.allFinite() || shift.norm() > kMaxLocalShift * side) return std::nullopt;
  return corners;
}

}  // namespace

std::optional<GridAlignment> AlignGrid(const AprilGridTarget& target, const cv::Mat& gray,
                                       const std::vector<SeedTag>& seeds) {
  auto H = seeds.empty() ? std::nullopt : AlignFromSeeds(target, gray, seeds);
  // Without seeds, or seeds that do not line the grid up (too small for
  // their corners, or one misread): the outlines, provided the decoded tags
  // mostly lie where they put them.
  if (!H) {
    // The sheet's bright outline; where none lines up, the dark one inside
    // its margin (the bright one joined to what lies behind the sheet).
    cv::Mat bright;
    cv::adaptiveThreshold(gray, bright, 255, cv::ADAPTIVE_THRESH_MEAN_C, cv::THRESH_BINARY,
                          kThresholdBlockPx, -kThresholdOffset);
    H = AlignFromOutlines(target, gray, SheetOutlines(gray, bright, target), 4,
                          kMinCoarseCorrelation);
    // Inside the margin the print's texture lines up in part in every turn
    // (on a METRIC image with no grid in it all four passed the sheet's
    // coarse test): only the turn that lines up best, and clearly, is aligned
    // in full.
    if (!H)
      H = AlignFromOutlines(target, gray, InsideOutlines(gray, bright, target), 1,
                            kMinInsideCoarseCorrelation);
    if (H && 3 * SeedsOff(target, seeds, *H, kSeedContradiction) > static_cast<int>(seeds.size()))
      H.reset();
  }
  if (!H) return std::nullopt;
  // The grid as a whole must follow the print (seeds alone can be lined up
  // with a wrong neighbourhood), and most of its tags in the image be seen.
  const auto correlation = GridCorrelation(target, gray, *H);
  if (!correlation || *correlation < kMinGridCorrelation) return std::nullopt;
  GridAlignment alignment;
  alignment.H_image_target = *H;
  const auto prediction = Predict(target, gray, *H);
  int in_image = 0, seen_tags = 0;
  for (int tag = 0; tag < target.NumTags(); ++tag) {
    const auto seen = TagSeen(target, gray, *H, tag);
    in_image += seen.has_value();
    if (!seen.value_or(false)) continue;
    ++seen_tags;
    if (!prediction) continue;
    if (const auto corners = LocalCorners(target, gray, *H, *prediction, tag))
      alignment.tags.push_back({tag, *corners});
  }
  if (2 * seen_tags < in_image) return std::nullopt;
  return alignment;
}

}  // namespace handeye::internal
