// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/checkerboard.h"

#include <cmath>

#include "handeye/core/error.h"
#include "handeye/core/input_limits.h"

namespace handeye {

const TargetPoint* Target::FindPoint(int id) const {
  const auto& pts = Points();
  // Ids are usually 0..n-1 in order; fall back to a scan otherwise.
  if (id >= 0 && id < static_cast<int>(pts.size()) && pts[id].id == id) return &pts[id];
  for (const auto& p : pts)
    if (p.id == id) return &p;
  return nullptr;
}

CheckerboardTarget::CheckerboardTarget(const TargetSpec& spec) : spec_(spec) {
  spec.RejectUnknownKeys({"inner_corners", "square_size_m"});
  const auto corners = spec.GetIntPair("inner_corners", 2);
  cols_ = corners[0];
  rows_ = corners[1];
  square_m_ = spec.GetPositive("square_size_m");
  Build();
}

CheckerboardTarget::CheckerboardTarget(int cols, int rows, double square_size_m)
    : cols_(cols), rows_(rows), square_m_(square_size_m) {
  if (cols < 2 || rows < 2) throw InputError("", "/inner_corners", "expected two integers >= 2");
  if (!(square_size_m > 0) || !std::isfinite(square_size_m))
    throw InputError("", "/square_size_m", "expected a positive number");
  spec_.type = "checkerboard";
  spec_.values["inner_corners"] = std::vector<double>{double(cols), double(rows)};
  spec_.values["square_size_m"] = square_size_m;
  Build();
}

void CheckerboardTarget::Build() {
  RequireTargetPointsWithinLimit(cols_, rows_, "/inner_corners");
  points_.clear();
  points_.reserve(static_cast<std::size_t>(cols_) * rows_);
  for (int j = 0; j < rows_; ++j)
    for (int i = 0; i < cols_; ++i)
      points_.push_back({j * cols_ + i, Eigen::Vector3d(i * square_m_, j * square_m_, 0.0)});
}

Eigen::AlignedBox2d CheckerboardTarget::Extent() const {
  // (cols+1) x (rows+1) squares starting one square before corner (0, 0), plus
  // one square of white margin all round.
  return Eigen::AlignedBox2d(Eigen::Vector2d(-2 * square_m_, -2 * square_m_),
                             Eigen::Vector2d((cols_ + 1) * square_m_, (rows_ + 1) * square_m_));
}

double CheckerboardTarget::Albedo(double x_m, double y_m) const {
  const int a = static_cast<int>(std::floor(x_m / square_m_));
  const int b = static_cast<int>(std::floor(y_m / square_m_));
  if (a < -1 || b < -1 || a > cols_ - 1 || b > rows_ - 1) return 1.0;  // margin
  return ((a + b) % 2 == 0) ? 0.0 : 1.0;
}

std::vector<std::string> CheckerboardTarget::Warnings() const {
  if (!IsAmbiguous()) return {};
  return {"checkerboard " + std::to_string(cols_) + "x" + std::to_string(rows_) +
          " inner corners is 180-degree ambiguous (cols + rows is even): corner ids may be "
          "flipped between views; prefer a board with cols + rows odd, e.g. " +
          std::to_string(cols_) + "x" + std::to_string(rows_ + 1)};
}

}  // namespace handeye
