// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// A small cell whose observations are projected, not rendered: for the
/// command-line tests that need a calibration in a second, not images.

#include <cstdint>
#include <string>

#include "handeye/sim/synthetic.h"

namespace handeye::test {

/// The small cell with 2 cameras, a 7×4 checkerboard of 40 mm squares and
/// `poses` robot poses (drawn from `pose_seed` when it is not 0), cam0
/// knocked by 5 mm / 0.2° when `bumped`, with the visible points projected
/// plus 0.1 px of noise as its observations.
SyntheticScene ProjectedSmallCell(int poses, std::uint64_t pose_seed = 0, bool bumped = false);

/// ProjectedSmallCell(poses) saved as DIR/obs.json and calibrated into
/// DIR/result.json (REQUIREd to succeed); returns calibrate's output.
std::string CalibratedSmallCell(const std::string& dir, int poses = 8);

/// The mean camera position error (mm) of the result file against the
/// simulator's ground-truth file.
double MeanCameraErrorMm(const std::string& result_path, const std::string& truth_path);

}  // namespace handeye::test
