// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once

#include <memory>

#include "handeye/core/checkerboard.h"
#include "handeye/detectors/detector.h"

namespace handeye {

/// Checkerboard detector: OpenCV corner finding, sub-pixel refinement, then
/// ids by SPEC §4's black-square rule, so that a board seen rotated or upside
/// down gives the same ids to the same physical corners (up to the 180° flip
/// that ambiguous boards, cols + rows even, cannot resolve).
class CheckerboardDetector : public Detector {
 public:
  /// Shares ownership of the target; `target` must not be null.
  explicit CheckerboardDetector(std::shared_ptr<const CheckerboardTarget> target);
  /// Every inner corner, or nullopt when the whole board is not found.
  std::optional<Detection> Detect(const cv::Mat& gray) const override;
  /// Detect(); a board found whose squares' colours fit only the transposed
  /// size (the images show rows x cols inner corners, cols and rows both odd:
  /// the one case where the declared board's colours cannot fit) names the
  /// size to declare.
  std::optional<Detection> DetectOrExplain(const cv::Mat& gray,
                                           std::string* mismatch) const override;

 private:
  std::shared_ptr<const CheckerboardTarget> target_;
};

}  // namespace handeye
