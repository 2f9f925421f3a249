// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// ChArUco board geometry and print (SPEC §4, OpenCV 4.6 layout).

#include <array>
#include <vector>

#include "handeye/core/marker_codebook.h"
#include "handeye/core/target.h"

namespace handeye {

/// ChArUco board (SPEC §4): `squares` [sx, sy], `square_size_m` L,
/// `marker_size_m` m < L, `dictionary` (an OpenCV predefined dictionary name).
///
/// OpenCV 4.6 layout (cv::aruco::CharucoBoard::create): square (a, b) covers
/// [a·L, (a+1)·L] × [b·L, (b+1)·L]; it is black when a + b is even, so square
/// (0, 0) is black; every white square holds one marker, numbered 0, 1, ...
/// in row-major order (b, then a), centred in its square with the
/// dictionary's 1-cell black border. As printed and seen from the front (the
/// target's -z side), x points right and y down; markers are upright.
/// Inner corner (x, y), x < sx-1, y < sy-1, has id y·(sx−1)+x and lies at
/// ((x+1)·L, (y+1)·L, 0). The sheet adds a white margin of (L − m)/2, the
/// markers' own quiet zone, around the sx × sy squares.
///
/// `layout` "legacy" (default "opencv"): a board printed by OpenCV before 4.6
/// (OpenCV 4.7's setLegacyPattern(true)). Those boards were laid out from a
/// black bottom-left square, so with sy even square (0, 0) is white: square
/// (a, b) is black when a + b is odd, markers fill the white squares in the
/// same row-major order, and corner ids and positions are as above. With sy
/// odd the two layouts are the same board.
///
/// Optional key read by the detector, accepted here: `min_corners`.
class CharucoTarget : public Target {
 public:
  /// `dictionary` is the code book named by `spec`'s `dictionary` (the
  /// detectors library resolves names to OpenCV's predefined dictionaries).
  /// Throws InputError (paths relative to the target object) on bad values,
  /// a name that differs from the code book's, or a board that needs more
  /// markers than the dictionary has.
  CharucoTarget(const TargetSpec& spec, MarkerCodebook dictionary);

  std::string Type() const override { return "charuco"; }
  const TargetSpec& Spec() const override { return spec_; }
  const std::vector<TargetPoint>& Points() const override { return points_; }
  Eigen::AlignedBox2d Extent() const override;
  /// O(1): square and marker lookups in precomputed tables.
  double Albedo(double x_m, double y_m) const override;

  int squares_x() const { return squares_x_; }
  int squares_y() const { return squares_y_; }
  double square_size_m() const { return square_m_; }
  double marker_size_m() const { return marker_m_; }
  const MarkerCodebook& dictionary() const { return dictionary_; }
  /// `layout` "legacy": laid out as OpenCV before 4.6 printed the board.
  bool legacy() const { return legacy_; }
  /// Markers on the board: one per white square, ids 0 .. NumMarkers()-1.
  int NumMarkers() const { return static_cast<int>(marker_square_.size()); }
  /// Marker id in square (a, b); -1 for a black square or outside the board.
  int MarkerInSquare(int a, int b) const;
  /// Corners of marker `id` in the target frame in OpenCV's order: top-left,
  /// top-right, bottom-right, bottom-left as printed (clockwise on the print
  /// seen from the front). `id` must be in [0, NumMarkers()).
  std::array<Eigen::Vector3d, 4> MarkerCorners(int id) const;
  /// The two markers in the white squares that touch inner corner `corner_id`.
  std::array<int, 2> MarkersAtCorner(int corner_id) const;

 private:
  TargetSpec spec_;
  MarkerCodebook dictionary_;
  int squares_x_ = 0, squares_y_ = 0;
  double square_m_ = 0, marker_m_ = 0, margin_m_ = 0;
  bool legacy_ = false;
  std::vector<TargetPoint> points_;
  std::vector<int> square_marker_;                 ///< per square, row-major; -1 black
  std::vector<std::array<int, 2>> marker_square_;  ///< per marker: (a, b)
};

}  // namespace handeye
