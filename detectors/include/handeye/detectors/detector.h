// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The detector interface every target plugin implements.

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <vector>

namespace handeye {

/// What a detector found in one image: target point ids (Target::Points()) and
/// their sub-pixel positions (pixel centres at integer coordinates, SPEC §2).
struct Detection {
  std::vector<int> ids;                    ///< TargetPoint::id, unique
  std::vector<Eigen::Vector2d> points_px;  ///< one per id, pixels
};

/// Finds a target in an 8-bit single-channel image. Implementations are
/// stateless after construction: Detect() may be called from several threads.
class Detector {
 public:
  virtual ~Detector() = default;
  /// nullopt when the target is not found (an expected outcome, not an error).
  /// `gray`: CV_8UC1, not modified; the detector keeps no reference to it.
  virtual std::optional<Detection> Detect(const cv::Mat& gray) const = 0;
};

}  // namespace handeye
