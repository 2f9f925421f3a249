// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// One rule for the ChArUco and AprilGrid detectors' options: what the target
// object says, and the fewest corners for a view no more than the target has.

#include <algorithm>

#include "handeye/core/target.h"

namespace handeye::internal {

/// `Options::FromSpec(target.Spec())`; without the spec's own `min_corners`,
/// a view needs no more corners than the whole target has (a small board's
/// every corner; the default of eight could never be met by a 3 × 3 ChArUco
/// board or a grid of one tag), and never fewer than a pose needs (four).
template <typename Options>
Options OptionsOfTarget(const Target& target) {
  Options options = Options::FromSpec(target.Spec());
  if (!target.Spec().Has("min_corners")) {
    const int all = static_cast<int>(target.Points().size());
    options.min_corners = std::max(4, std::min(options.min_corners, all));
  }
  return options;
}

}  // namespace handeye::internal
