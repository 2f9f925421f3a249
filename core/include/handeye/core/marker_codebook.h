// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Bit patterns of square binary markers (ArUco dictionaries, AprilTag
/// families) as plain data. The code books themselves come from the libraries
/// that decode them (OpenCV aruco, libapriltag), which only the detectors
/// link; targets in core receive them, so that core's geometry and texture do
/// not depend on those libraries.

#include <cstdint>
#include <string>
#include <vector>

namespace handeye {

/// The printed data cells of every marker of one dictionary or family,
/// without the black border. `codes[id]` holds `bits`×`bits` cells row-major,
/// top row first, as the marker is printed upright (the way the library draws
/// it: cv::aruco::drawMarker, apriltag_to_image); 1 = white, 0 = black.
struct MarkerCodebook {
  std::string name;  ///< e.g. "DICT_5X5_100", "tag36h11"
  int bits = 0;      ///< data cells per side, e.g. 5 for DICT_5X5_*, 6 for tag36h11
  std::vector<std::vector<std::uint8_t>> codes;

  /// True when `bits` > 0 and every code has bits² cells of value 0 or 1.
  bool Valid() const {
    if (bits <= 0) return false;
    for (const auto& code : codes) {
      if (code.size() != static_cast<std::size_t>(bits) * bits) return false;
      for (std::uint8_t cell : code)
        if (cell > 1) return false;
    }
    return true;
  }
};

}  // namespace handeye
