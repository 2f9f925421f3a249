// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Kalibr's AprilGrid target: geometry and print (SPEC §4).

#include <array>
#include <vector>

#include "handeye/core/marker_codebook.h"
#include "handeye/core/target.h"

namespace handeye {

/// Kalibr's AprilGrid (SPEC §4): `tags` [cols, rows], `tag_size_m` s (edge of
/// a tag's black square), `tag_spacing` (gap between tags ÷ s, in (0, 1]),
/// `family` (default "tag36h11"), `border_bits` (1 or 2, default 2). Kalibr's
/// YAML names `tagCols`, `tagRows`, `tagSize`, `tagSpacing` are accepted
/// instead of `tags`, `tag_size_m`, `tag_spacing`; Spec() holds the latter.
///
/// The print is Kalibr's (kalibr_create_target_pdf): tags upright, tag ids
/// row-major from tag 0 at the bottom-left as the sheet is seen from the
/// front, each tag a `border_bits`-wide black frame around the family's data
/// cells, and a black square of the gap's size at every gap crossing and
/// around the outside, touching the tag corners diagonally (so every tag
/// corner is a checkerboard-like X junction).
///
/// Points: four per tag, Kalibr's index layout. With g = spacing·s and
/// p = s + g, point (c, r), c < 2·cols, r < 2·rows, has id r·2·cols + c and
/// Kalibr coordinates X = ⌊c/2⌋·p + (c mod 2)·s, Y = ⌊r/2⌋·p + (r mod 2)·s
/// (Y up the sheet). Tag t = j·cols + i has the corners (2i, 2j) bottom-left,
/// (2i+1, 2j) bottom-right, (2i+1, 2j+1) top-right, (2i, 2j+1) top-left.
///
/// Target frame: Kalibr's has z out of the printed face, but handeye targets
/// are seen from their -z side (target.h), so this frame is Kalibr's turned
/// 180° about x: a point is at (X, −Y, 0). Ids and in-plane distances are
/// Kalibr's; x points right and y down the sheet seen from the front, as for
/// the checkerboard and ChArUco. T_kalibrtarget_target = diag(1, −1, −1).
/// The sheet adds a white margin of one gap outside the outer black squares.
///
/// `first_id` (default 0, Kalibr's numbering) is the family id of tag 0: a
/// grid printed with ids from N on, or one tag of id N alone (tags [1, 1],
/// `first_id` N, as ViSP's and many hand-eye captures use). Point ids count
/// from 0 whatever it is.
///
/// Optional keys read by the detector, accepted here: `min_corners`,
/// `min_border_px`.
class AprilGridTarget : public Target {
 public:
  /// `family` is the code book named by `spec`'s `family` (the detectors
  /// library takes it from libapriltag). Throws InputError (paths relative to
  /// the target object) on bad values, a name that differs from the code
  /// book's, or more tags than the family has.
  AprilGridTarget(const TargetSpec& spec, MarkerCodebook family);

  std::string Type() const override { return "aprilgrid"; }
  const TargetSpec& Spec() const override { return spec_; }
  const std::vector<TargetPoint>& Points() const override { return points_; }
  Eigen::AlignedBox2d Extent() const override;
  /// O(1): arithmetic on the grid's pitch plus one table lookup.
  double Albedo(double x_m, double y_m) const override;

  int tags_x() const { return cols_; }
  int tags_y() const { return rows_; }
  int NumTags() const { return cols_ * rows_; }
  double tag_size_m() const { return tag_m_; }
  /// Gap between neighbouring tags ÷ tag size (Kalibr's tagSpacing).
  double tag_spacing() const { return spacing_; }
  int border_bits() const { return border_bits_; }
  /// The family id of tag 0 (tag t carries id first_id() + t).
  int first_id() const { return first_id_; }
  const MarkerCodebook& family() const { return family_; }
  /// Point ids of tag `tag_id`'s corners as printed: bottom-left,
  /// bottom-right, top-right, top-left (Kalibr's order).
  std::array<int, 4> TagCornerIds(int tag_id) const;

 private:
  TargetSpec spec_;
  MarkerCodebook family_;
  int cols_ = 0, rows_ = 0, border_bits_ = 2, first_id_ = 0;
  double tag_m_ = 0, spacing_ = 0, gap_m_ = 0, pitch_m_ = 0, bit_m_ = 0;
  std::vector<TargetPoint> points_;
};

}  // namespace handeye
