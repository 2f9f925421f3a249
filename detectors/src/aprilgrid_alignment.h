// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// An AprilGrid placed whole when its tags are too small to decode or fit:
// seen obliquely from a cell camera's distance most tags are a few pixels
// across the tilt, but the print as a whole still lines up with the image,
// and each tag's grey levels still follow its code.
// Internal to the detectors library.

#include <Eigen/Core>
#include <array>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <vector>

#include "handeye/core/aprilgrid.h"

namespace handeye::internal {

/// A tag the library decoded: its index on the grid and its corners in
/// TagCornerIds() order (pixels, SPEC §2).
struct SeedTag {
  int tag = 0;
  std::array<Eigen::Vector2d, 4> corners_px;
};

/// The grid aligned with the image: the homography from the board (metres,
/// x and y of TargetPoint::p_target) to pixels, and the tags seen under it.
struct GridAlignment {
  Eigen::Matrix3d H_image_target = Eigen::Matrix3d::Identity();
  /// The tags seen, ascending, with their corners (TagCornerIds() order,
  /// pixels): H's, shifted by the alignment of the tag's neighbourhood with
  /// the print blurred as the image is (a tag whose neighbourhood does not
  /// line up is left out).
  std::vector<SeedTag> tags;
};

/// Lines the rendered print up with `gray` (8-bit) by maximising their
/// correlation (cv::findTransformECC), from the homography of the decoded
/// `seeds`, or, with none (or seeds it does not line up: their corners more
/// than a tenth of their side off), from each outline that may be the sheet's
/// (bright: its margin; dark: its tags and the squares between them, inside
/// the margin), in each of its four turns; an outline's alignment needs a third
/// of the seeds or fewer more than half their side off (placed elsewhere),
/// and a correlation of the grid's data cells
/// with the print kMinGridLead ahead of any other's.
///
/// nullopt when nothing lines up, when the grid's data cells correlate with
/// the print under kMinGridCorrelation, or when under half of its tags in the
/// image are seen. A tag is seen when the grey levels of its cells and the
/// gap around it correlate with the print at kMinTagCorrelation or more (its
/// black border against the white gap stays clear when its data cells blur
/// together), and its own cells' at kMinOwnCorrelation or more (something in
/// front of the tag, the gap around it in view, fails this).
std::optional<GridAlignment> AlignGrid(const AprilGridTarget& target, const cv::Mat& gray,
                                       const std::vector<SeedTag>& seeds);

/// The least correlation of the grid's data cells with the print for an
/// alignment, and the least lead of an outline's over any other. On rendered
/// oblique views right alignments reached 0.45-0.8, those from wrong outlines
/// or turns 0.15 at most.
constexpr double kMinGridCorrelation = 0.4, kMinGridLead = 0.15;

/// The least correlations for a tag to count as seen.
constexpr double kMinTagCorrelation = 0.5, kMinOwnCorrelation = 0.3;

}  // namespace handeye::internal
