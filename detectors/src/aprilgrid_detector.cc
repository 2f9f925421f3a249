// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/detectors/aprilgrid_detector.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <utility>

#include "aprilgrid_alignment.h"
#include "corner_refinement.h"
#include "handeye/core/error.h"
#include "target_options.h"

namespace handeye {
namespace {

/// libapriltag's description of a family, owned for the lifetime of a scope.
struct StockFamily {
  explicit StockFamily(const std::string& name) {
    if (name == "tag36h11") {
      family = tag36h11_create();
      destroy = tag36h11_destroy;
      return;
    }
    std::string list;
    for (const auto& known : AprilTagFamilyNames()) list += (list.empty() ? "" : ", ") + known;
    throw InputError("", "/family", "unsupported tag family '" + name + "'; expected " + list);
  }
  ~StockFamily() { destroy(family); }
  StockFamily(const StockFamily&) = delete;
  StockFamily& operator=(const StockFamily&) = delete;

  /// Data cells per side, and where they start in the library's bit
  /// coordinates (which count from the black border's outer edge).
  int bits() const { return static_cast<int>(std::lround(std::sqrt(family->nbits))); }
  int offset() const { return (family->width_at_border - bits()) / 2; }

  apriltag_family_t* family = nullptr;
  void (*destroy)(apriltag_family_t*) = nullptr;
};

/// libapriltag reports pixel centres at +0.5 (it samples pixel ⌊x⌋ for x);
/// SPEC §2 puts them at integers.
constexpr double kLibraryPixelOffset = 0.5;

/// Tags whose shortest side is below this (pixels; 1.5 px per cell) are
/// decoded but left out: their edges are too blurred to fit. On rendered
/// grids, corners of tags with a 10-15 px shortest side were off by 0.28 px
/// on average, 15-20 px by 0.08 px, 20 px and more by 0.03-0.05 px.
constexpr double kMinSidePx = 15.0;

/// Gammas of the brightenings applied to the library's copies of the image,
/// one detection pass each (see DetectRawTags).
constexpr double kGammas[] = {0.25, 0.1};

}  // namespace

std::vector<std::string> AprilTagFamilyNames() { return {"tag36h11"}; }

MarkerCodebook AprilTagCodebook(const std::string& family_name) {
  const StockFamily stock(family_name);
  const apriltag_family_t& f = *stock.family;
  const int n = stock.bits(), offset = stock.offset();
  MarkerCodebook book;
  book.name = family_name;
  book.bits = n;
  book.codes.reserve(f.ncodes);
  for (std::uint32_t id = 0; id < f.ncodes; ++id) {
    // Bit i of the code, counted from the most significant, is the cell at
    // (bit_x[i], bit_y[i]); 1 is white (apriltag_to_image).
    std::vector<std::uint8_t> code(static_cast<std::size_t>(n) * n, 0);
    for (std::uint32_t i = 0; i < f.nbits; ++i) {
      const int x = static_cast<int>(f.bit_x[i]) - offset,
                y = static_cast<int>(f.bit_y[i]) - offset;
      if (x < 0 || y < 0 || x >= n || y >= n)
        throw std::logic_error("AprilTagCodebook: " + family_name +
                               " is not a classic square layout");
      code[static_cast<std::size_t>(y) * n + x] = (f.codes[id] >> (f.nbits - 1 - i)) & 1u;
    }
    book.codes.push_back(std::move(code));
  }
  return book;
}

std::shared_ptr<const AprilGridTarget> MakeAprilGridTarget(const TargetSpec& spec) {
  auto target = std::make_shared<const AprilGridTarget>(
      spec, AprilTagCodebook(spec.GetString("family", "tag36h11")));
  AprilGridDetector::Options::FromSpec(spec);
  return target;
}

bool AprilGridDetector::Options::Check(std::string* why) const {
  auto fail = [why](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  if (min_corners < 4) return fail("min_corners >= 4 (a pose needs four points)");
  if (!(min_border_px >= 0) || !std::isfinite(min_border_px)) return fail("min_border_px >= 0");
  if (max_bits_corrected < 0 || max_bits_corrected > 3) return fail("max_bits_corrected in [0, 3]");
  return true;
}

AprilGridDetector::Options AprilGridDetector::Options::FromSpec(const TargetSpec& spec) {
  Options options;
  if (spec.Has("min_corners")) options.min_corners = spec.GetInt("min_corners", 4);
  if (spec.Has("min_border_px")) {
    const auto* px = std::get_if<double>(&spec.values.at("min_border_px"));
    if (!px || !std::isfinite(*px) || *px < 0)
      throw InputError("", "/min_border_px", "expected a distance in pixels >= 0");
    options.min_border_px = *px;
  }
  return options;
}

/// One libapriltag detector with its own copy of the grid's family (the
/// library keeps its decoding table inside the family, so a family serves
/// one detector). Not thread-safe: the pool hands each Detect() its own.
struct AprilGridDetector::Engine {
  Engine(const AprilGridTarget& target, int max_bits_corrected) {
    const StockFamily stock(target.family().name);
    const apriltag_family_t& f = *stock.family;
    // Only the grid's own tags: a smaller decoding table, and any other
    // tag36h11 tag in view cannot be mistaken for one of ours.
    codes.assign(f.codes + target.first_id(), f.codes + target.first_id() + target.NumTags());
    // The bit positions count from the outer edge of the black border;
    // widening the border shifts them inwards.
    const int extra = target.border_bits() - stock.offset();
    for (std::uint32_t i = 0; i < f.nbits; ++i) {
      bit_x.push_back(static_cast<std::uint32_t>(static_cast<int>(f.bit_x[i]) + extra));
      bit_y.push_back(static_cast<std::uint32_t>(static_cast<int>(f.bit_y[i]) + extra));
    }
    name = f.name;
    family.ncodes = static_cast<std::uint32_t>(codes.size());
    family.codes = codes.data();
    family.width_at_border = stock.bits() + 2 * target.border_bits();
    family.total_width = family.width_at_border + 2;  // plus the white ring
    family.reversed_border = false;
    family.nbits = f.nbits;
    family.bit_x = bit_x.data();
    family.bit_y = bit_y.data();
    family.h = f.h;
    family.name = name.data();
    family.impl = nullptr;

    detector = apriltag_detector_create();
    detector->nthreads = 1;  // images are detected in parallel instead
    // Full resolution: tags down to 20 px have 2 px per bit, which
    // decimation would halve.
    detector->quad_decimate = 1.0f;
    detector->quad_sigma = 0.0f;  // also keeps the library from writing to our image
    detector->refine_edges = true;
    // Sharpen the sampled cells more than the default 0.25: small tags
    // (12-20 px, 2 px per cell) blur their cells into each other. Measured on
    // rendered grids: 79 % of their corners found at 0.25, 91 % at 0.75;
    // tags of 20 px and more were found either way.
    detector->decode_sharpening = 0.75;
    apriltag_detector_add_family_bits(detector, &family, max_bits_corrected);
  }
  ~Engine() {
    // Also frees the decoding table the library hung on `family`.
    apriltag_detector_destroy(detector);
  }
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  std::vector<std::uint64_t> codes;
  std::vector<std::uint32_t> bit_x, bit_y;
  std::string name;
  apriltag_family_t family{};
  apriltag_detector_t* detector = nullptr;
};

AprilGridDetector::AprilGridDetector(std::shared_ptr<const AprilGridTarget> target)
    : AprilGridDetector(target, target ? internal::OptionsOfTarget<Options>(*target) : Options()) {}

AprilGridDetector::AprilGridDetector(std::shared_ptr<const AprilGridTarget> target,
                                     const Options& options)
    : target_(std::move(target)), options_(options) {
  if (!target_) throw std::invalid_argument("AprilGridDetector: null target");
  std::string why;
  if (!options_.Check(&why)) throw std::invalid_argument("AprilGridDetector: expected " + why);
  // Fail here, not in the first Detect(), if the family cannot be built.
  Return(Borrow());
}

AprilGridDetector::~AprilGridDetector() = default;

std::unique_ptr<AprilGridDetector::Engine> AprilGridDetector::Borrow() const {
  {
    std::lock_guard<std::mutex> lock(pool_mutex_);
    if (!pool_.empty()) {
      std::unique_ptr<Engine> engine = std::move(pool_.back());
      pool_.pop_back();
      return engine;
    }
  }
  return std::make_unique<Engine>(*target_, options_.max_bits_corrected);
}

void AprilGridDetector::Return(std::unique_ptr<Engine> engine) const {
  std::lock_guard<std::mutex> lock(pool_mutex_);
  pool_.push_back(std::move(engine));
}

std::vector<AprilGridDetector::RawTag> AprilGridDetector::DetectRawTags(const cv::Mat& gray) const {
  if (gray.empty() || gray.type() != CV_8UC1)
    throw std::invalid_argument("AprilGridDetector: expected an 8-bit single-channel image");
  // libapriltag segments the image into connected black and white regions.
  // Kalibr's black corner squares touch the tags at single points, and the
  // blurred pixels there, about half grey, join every tag and square into one
  // black region that is no quad. Brightening the mid-greys before the library
  // sees the image (a gamma curve; the decoder's thresholds adapt, data cells
  // stay black or white) cuts those joins: on rendered grids turned in the
  // image, 8 % of the tags were found without it. No one curve suits all
  // views: gamma 0.25 found the most small tags (84 % of 15-20 px ones),
  // 0.1 the most large, strongly foreshortened ones; the union of both
  // passes is kept.
  std::unique_ptr<Engine> engine = Borrow();
  auto brighten = [&gray](double gamma) {
    cv::Mat lut(1, 256, CV_8U);
    for (int i = 0; i < 256; ++i)
      lut.at<std::uint8_t>(i) = cv::saturate_cast<std::uint8_t>(255.0 * std::pow(i / 255.0, gamma));
    cv::Mat brightened;
    cv::LUT(gray, lut, brightened);
    return brightened;
  };
  std::vector<RawTag> tags;
  for (const double gamma : kGammas) {
    cv::Mat brightened = brighten(gamma);
    // The library only reads the image (quad_sigma = 0, no decimation).
    image_u8_t image{brightened.cols, brightened.rows,
                     static_cast<std::int32_t>(brightened.step[0]),
                     brightened.ptr<std::uint8_t>(0)};
    zarray_t* detections = apriltag_detector_detect(engine->detector, &image);
    for (int i = 0; i < zarray_size(detections); ++i) {
      apriltag_detection_t* det = nullptr;
      zarray_get(detections, i, &det);
      RawTag tag;
      tag.id = det->id;
      tag.hamming = det->hamming;
      // p[0..3] are the tag-frame corners (-1, 1), (1, 1), (1, -1), (-1, -1)
      // with y down the upright tag: bottom-left, bottom-right, top-right,
      // top-left, the order of TagCornerIds().
      for (int k = 0; k < 4; ++k)
        tag.corners_px[k] =
            Eigen::Vector2d(det->p[k][0] - kLibraryPixelOffset, det->p[k][1] - kLibraryPixelOffset);
      // The same tag from an earlier pass (same id, same place) is kept once;
      // the same id elsewhere is a second copy, left for Detect() to drop.
      const auto same = std::find_if(tags.begin(), tags.end(), [&tag](const RawTag& other) {
        const double side = (other.corners_px[1] - other.corners_px[0]).norm();
        return other.id == tag.id && (other.corners_px[0] - tag.corners_px[0]).norm() < 0.25 * side;
      });
      if (same == tags.end()) tags.push_back(tag);
    }
    apriltag_detections_destroy(detections);
    // Every tag of the grid found: no need for another pass. No tag of the
    // grid in the first: most likely an image without the grid (Detect
    // still looks for its outline).
    if (static_cast<int>(tags.size()) >= target_->NumTags()) break;
    if (options_.first_stage && tags.empty()) break;
  }
  Return(std::move(engine));
  return tags;
}

std::optional<Detection> AprilGridDetector::Detect(const cv::Mat& gray) const {
  const std::vector<RawTag> tags = DetectRawTags(gray);
  std::map<int, int> copies;
  for (const RawTag& tag : tags) ++copies[tag.id];

  const int cells = target_->family().bits + 2 * target_->border_bits();
  std::vector<std::pair<int, Eigen::Vector2d>> found;
  auto inside = [&](const Eigen::Vector2d& uv) {
    const double m = options_.min_border_px;
    return uv.x() >= m && uv.y() >= m && uv.x() <= gray.cols - 1 - m && uv.y() <= gray.rows - 1 - m;
  };
  for (const RawTag& tag : tags) {
    // A tag seen twice (another grid in view) cannot be placed.
    if (tag.id < 0 || tag.id >= target_->NumTags() || copies[tag.id] != 1) continue;
    // The shortest side: bands must fit the most foreshortened direction.
    double side_px = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 4; ++k)
      side_px = std::min(side_px, (tag.corners_px[(k + 1) % 4] - tag.corners_px[k]).norm());
    if (side_px < kMinSidePx) continue;
    // Each side of the tag is fitted as a straight edge, continued into the
    // black corner squares whose sides are collinear with it, in a band that
    // stays clear of the tag's data cells (the border's width inside) and of
    // the corner squares' far sides (a gap outside); the corners are where
    // neighbouring sides cross.
    const double gap_px = target_->tag_spacing() * side_px;
    const double border_px = target_->border_bits() * side_px / cells;
    const double half_width_px = std::clamp(0.45 * std::min(gap_px, border_px), 1.0, 4.0);
    std::array<internal::EdgeLine, 4> sides;
    bool usable = true;
    for (int k = 0; k < 4 && usable; ++k) {
      const auto line = internal::FitEdge(gray, tag.corners_px[k], tag.corners_px[(k + 1) % 4],
                                          0.8 * gap_px, half_width_px + 1.0, half_width_px);
      usable = line.has_value();
      if (usable) sides[k] = *line;
    }
    std::array<Eigen::Vector2d, 4> refined;
    const double max_shift_px = std::max(2.0, 0.15 * side_px);
    for (int k = 0; k < 4 && usable; ++k) {
      const auto corner = internal::Intersect(sides[(k + 3) % 4], sides[k]);
      usable = corner && (*corner - tag.corners_px[k]).norm() <= max_shift_px && inside(*corner);
      if (usable) refined[k] = *corner;
    }
    // All four or none: a side that does not fit means the quad (or the
    // print near it) is not what it seems.
    if (!usable) continue;
    const auto ids = target_->TagCornerIds(tag.id);
    for (int k = 0; k < 4; ++k) found.emplace_back(ids[k], refined[k]);
  }

  // Tags too small to fit, or not decoded at all: the print lined up with
  // the image, from the tags that did decode or from the sheet's outline,
  // places every tag whose grey levels follow it (internal::AlignGrid).
  if (static_cast<int>(found.size()) < 4 * target_->NumTags()) {
    std::vector<internal::SeedTag> seeds;
    for (const RawTag& tag : tags)
      if (tag.id >= 0 && tag.id < target_->NumTags() && copies[tag.id] == 1)
        seeds.push_back({tag.id, tag.corners_px});
    if (const auto alignment = internal::AlignGrid(*target_, gray, seeds)) {
      std::vector<bool> have(static_cast<std::size_t>(4 * target_->NumTags()), false);
      for (const auto& point : found) have[static_cast<std::size_t>(point.first)] = true;
      for (const internal::SeedTag& tag : alignment->tags) {
        const auto ids = target_->TagCornerIds(tag.tag);
        for (int k = 0; k < 4; ++k) {
          const std::size_t id = static_cast<std::size_t>(ids[k]);
          if (!have[id] && inside(tag.corners_px[k])) found.emplace_back(ids[k], tag.corners_px[k]);
        }
      }
    }
  }
  if (static_cast<int>(found.size()) < options_.min_corners) return std::nullopt;
  std::sort(found.begin(), found.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::Vector2d> on_board;
  for (const auto& [id, uv] : found) on_board.push_back(target_->FindPoint(id)->p_target.head<2>());
  if (!internal::SpansPlane(on_board, 0.5 * target_->tag_size_m())) return std::nullopt;

  Detection detection;
  for (const auto& [id, uv] : found) {
    detection.ids.push_back(id);
    detection.points_px.push_back(uv);
  }
  return detection;
}

}  // namespace handeye
