// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A ChArUco board's corners grown from its decoded markers: where the board
// is seen so obliquely that only its nearer markers decode, the squares'
// X-junctions are still there, one square apart on the board. Internal to
// the detectors library.

#include <Eigen/Core>
#include <functional>
#include <opencv2/core/types.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "handeye/core/charuco.h"

namespace handeye::internal {

/// Refines inner corner `id` of the board from `guess` (pixels, SPEC §2)
/// with the homography `H_image_target` (target plane, metres, to the image)
/// around it; nullopt when no X-junction is there within its tolerance.
using CharucoCornerRefiner = std::function<std::optional<Eigen::Vector2d>(
    int id, const Eigen::Matrix3d& H_image_target, const Eigen::Vector2d& guess)>;

/// Decoded markers that must all agree before corners are grown from them.
constexpr int kMinGrowthMarkers = 3;

/// The inner corners of `target` that grow from the decoded markers
/// (`marker_ids`, their image corners as cv::aruco::detectMarkers gives
/// them) and the corners already `found` (ids and pixels): each corner next
/// to known ones (corners found, corners of decoded markers) is predicted by
/// the homography of the known points within two squares of it, and kept
/// when `refine` finds its X-junction there; until no more grow. The
/// markers fix every id; the board's geometry, one square at a time, fixes
/// where each corner is. Nothing grows unless at least kMinGrowthMarkers
/// markers are decoded and every one of them lies where the homography of
/// all of them puts it (a misread marker would number the corners near it
/// wrongly). Returns only corners not in `found`.
std::vector<std::pair<int, Eigen::Vector2d>> GrowCharucoCorners(
    const CharucoTarget& target, const std::vector<int>& marker_ids,
    const std::vector<std::vector<cv::Point2f>>& marker_corners,
    const std::vector<std::pair<int, Eigen::Vector2d>>& found, const CharucoCornerRefiner& refine);

}  // namespace handeye::internal
