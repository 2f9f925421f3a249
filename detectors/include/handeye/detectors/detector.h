// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The detector interface every target plugin implements.

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
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
  /// Detect(); when it finds nothing although the image shows the target
  /// declared differently (a board the wrong way round, an older layout), a
  /// sentence for the user saying what to change in the target object is put
  /// in `*mismatch` (cleared otherwise; may be null). Declarations are checked
  /// only where that costs little beside the search (DetectAll asks on every
  /// image). The default only calls Detect().
  virtual std::optional<Detection> DetectOrExplain(const cv::Mat& gray,
                                                   std::string* mismatch) const {
    if (mismatch) mismatch->clear();
    return Detect(gray);
  }
};

}  // namespace handeye
