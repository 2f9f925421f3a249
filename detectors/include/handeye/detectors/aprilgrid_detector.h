// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// AprilGrid target plugin (Kalibr's target): tag family code books from
/// libapriltag and the detector (AprilTag 3, then checks and refinement).

#include <array>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "handeye/core/aprilgrid.h"
#include "handeye/detectors/detector.h"

namespace handeye {

/// The tag families an AprilGrid may use: "tag36h11" (Kalibr's).
std::vector<std::string> AprilTagFamilyNames();
/// A family's data cells as apriltag_to_image draws them (upright, 1 = white).
/// Throws InputError at `/family` for an unsupported name.
MarkerCodebook AprilTagCodebook(const std::string& family_name);
/// An AprilGridTarget for `spec`, its family taken from libapriltag; also
/// checks the detector's options in `spec`. Throws InputError.
std::shared_ptr<const AprilGridTarget> MakeAprilGridTarget(const TargetSpec& spec);

/// AprilGrid detector (SPEC §4). Tags are found by libapriltag (AprilTag 3)
/// with a family description of the grid's own tags whose black border is
/// `border_bits` wide (the stock tag36h11 description assumes 1 bit, Kalibr
/// prints 2), so the quads are the tags' outer black squares. Tags seen twice
/// are dropped, as are tags with a corner closer than `min_border_px` to the
/// image border (their edges may be cut off). Corners are moved from the
/// library's pixel convention (pixel centres at +0.5) to SPEC §2's, then
/// refined to the X junction each tag corner makes with Kalibr's black corner
/// square. Tags too small for that (under 15 px a side) or not decoded at
/// all (seen obliquely from afar) are placed by the print as a whole: lined
/// up with the image (ECC) from the decoded tags or, with none, from the
/// sheet's bright outline in each of its turns; a tag is placed when the
/// grid's grey levels follow the print and its own follow its code (one
/// covered or out of view is not). A view needs `min_corners` corners, not
/// all on one line.
class AprilGridDetector : public Detector {
 public:
  struct Options {
    /// Fewest corners for a view (target key `min_corners`); 8 = two tags
    /// (without the key, 4 for a grid of one tag).
    int min_corners = 8;
    /// Smallest distance of a tag corner from the image border, pixels
    /// (target key `min_border_px`; Kalibr's minBorderDistance is 4).
    double min_border_px = 4.0;
    /// Bit errors the decoder may correct (tag36h11 codes differ in ≥ 11).
    int max_bits_corrected = 2;
    /// Skip the library's second pass when its first finds no tag of the
    /// grid (the cheaper stage for images without it). Off only to compare
    /// against in tests.
    bool first_stage = true;

    bool Check(std::string* why) const;
    /// Defaults overridden by the target object's `min_corners`, `min_border_px`.
    static Options FromSpec(const TargetSpec& spec);
  };

  explicit AprilGridDetector(std::shared_ptr<const AprilGridTarget> target);
  AprilGridDetector(std::shared_ptr<const AprilGridTarget> target, const Options& options);
  ~AprilGridDetector() override;

  /// Thread-safe: each call borrows its own libapriltag detector from a pool.
  std::optional<Detection> Detect(const cv::Mat& gray) const override;

  /// One tag as libapriltag reports it, before any of the checks above:
  /// corners in SPEC §2 pixels in the order of TagCornerIds() (bottom-left,
  /// bottom-right, top-right, top-left of the printed tag).
  struct RawTag {
    int id = 0;
    int hamming = 0;
    std::array<Eigen::Vector2d, 4> corners_px;
  };
  /// libapriltag's tags in an image (exposed to pin the pixel convention in tests).
  std::vector<RawTag> DetectRawTags(const cv::Mat& gray) const;

 private:
  struct Engine;
  std::unique_ptr<Engine> Borrow() const;
  void Return(std::unique_ptr<Engine> engine) const;

  std::shared_ptr<const AprilGridTarget> target_;
  Options options_;
  mutable std::mutex pool_mutex_;
  mutable std::vector<std::unique_ptr<Engine>> pool_;
};

}  // namespace handeye
