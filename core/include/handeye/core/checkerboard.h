// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once

#include "handeye/core/target.h"

namespace handeye {

/// Checkerboard (SPEC §4): `inner_corners` [cols, rows], `square_size_m`.
/// Corner (i, j) has id j·cols + i and lies at (i·s, j·s, 0). The square on
/// the -x, -y side of corner (0, 0) is black; square (a, b), a in [-1, cols-1],
/// b in [-1, rows-1], covering [a·s, (a+1)·s] × [b·s, (b+1)·s], is black when
/// a + b is even. The sheet has a white margin of one square around the
/// (cols+1) × (rows+1) squares.
class CheckerboardTarget : public Target {
 public:
  /// Throws InputError (paths relative to the target object) on bad values.
  explicit CheckerboardTarget(const TargetSpec& spec);
  /// `cols` × `rows` inner corners (both >= 2), squares of `square_size_m` metres.
  CheckerboardTarget(int cols, int rows, double square_size_m);

  std::string Type() const override { return "checkerboard"; }
  const TargetSpec& Spec() const override { return spec_; }
  const std::vector<TargetPoint>& Points() const override { return points_; }
  Eigen::AlignedBox2d Extent() const override;
  double Albedo(double x_m, double y_m) const override;
  std::vector<std::string> Warnings() const override;

  int cols() const { return cols_; }                  ///< inner corners along x
  int rows() const { return rows_; }                  ///< inner corners along y
  double square_size_m() const { return square_m_; }  ///< metres
  /// True when cols + rows is even: the board looks the same turned by 180°,
  /// so no detector can tell (0, 0) from the opposite corner.
  bool IsAmbiguous() const { return (cols_ + rows_) % 2 == 0; }

 private:
  void Build();
  TargetSpec spec_;
  int cols_ = 0, rows_ = 0;
  double square_m_ = 0;
  std::vector<TargetPoint> points_;
};

}  // namespace handeye
