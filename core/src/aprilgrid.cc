// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/aprilgrid.h"

#include <algorithm>
#include <cmath>

#include "handeye/core/error.h"
#include "handeye/core/input_limits.h"

namespace handeye {
namespace {

/// `spec` with Kalibr's key names (tagCols, tagRows, tagSize, tagSpacing)
/// replaced by SPEC §4's, so the rest reads one spelling.
TargetSpec WithSpecKeyNames(const TargetSpec& spec) {
  TargetSpec out = spec;
  const bool kalibr_grid = spec.Has("tagCols") || spec.Has("tagRows");
  if (kalibr_grid && spec.Has("tags"))
    throw InputError("", spec.Has("tagCols") ? "/tagCols" : "/tagRows",
                     "expected either tags or Kalibr's tagCols and tagRows, not both");
  if (kalibr_grid) {
    const int cols = spec.GetInt("tagCols", 1), rows = spec.GetInt("tagRows", 1);
    out.values.erase("tagCols");
    out.values.erase("tagRows");
    out.values["tags"] = std::vector<double>{double(cols), double(rows)};
  }
  for (const auto& [kalibr, ours] : {std::pair<const char*, const char*>{"tagSize", "tag_size_m"},
                                     {"tagSpacing", "tag_spacing"}}) {
    if (!spec.Has(kalibr)) continue;
    if (spec.Has(ours))
      throw InputError(
          "", std::string("/") + kalibr,
          std::string("expected either ") + ours + " or Kalibr's " + kalibr + ", not both");
    out.values[ours] = spec.values.at(kalibr);
    out.values.erase(kalibr);
  }
  return out;
}

}  // namespace

AprilGridTarget::AprilGridTarget(const TargetSpec& spec, MarkerCodebook family)
    : family_(std::move(family)) {
  spec.RejectUnknownKeys({"tags", "tag_size_m", "tag_spacing", "family", "border_bits", "first_id",
                          "tagCols", "tagRows", "tagSize", "tagSpacing", "min_corners",
                          "min_border_px"});
  spec_ = WithSpecKeyNames(spec);
  const auto tags = spec_.GetIntPair("tags", 1);
  cols_ = tags[0];
  rows_ = tags[1];
  tag_m_ = spec_.GetPositive("tag_size_m");
  spacing_ = spec_.GetPositive("tag_spacing");
  // Kalibr's own limit; without a gap the black corner squares vanish and
  // neighbouring tags' borders touch.
  if (spacing_ > 1.0) throw InputError("", "/tag_spacing", "expected a gap ÷ tag size in (0, 1]");
  const std::string name = spec_.GetString("family", "tag36h11");
  if (name != family_.name || !family_.Valid())
    throw InputError("", "/family",
                     "expected the code book of family '" + name + "', got '" + family_.name + "'");
  border_bits_ = spec_.Has("border_bits") ? spec_.GetInt("border_bits", 1) : 2;
  if (border_bits_ > 2) throw InputError("", "/border_bits", "expected 1 or 2 (Kalibr prints 2)");
  RequireTargetPointsWithinLimit(2 * std::int64_t{cols_}, 2 * std::int64_t{rows_}, "/tags");
  first_id_ = spec_.Has("first_id") ? spec_.GetInt("first_id", 0) : 0;
  const int available = static_cast<int>(family_.codes.size()) - first_id_;
  if (first_id_ >= static_cast<int>(family_.codes.size()))
    throw InputError("", "/first_id",
                     "expected a tag id below " + std::to_string(family_.codes.size()) +
                         ", the size of family " + name);
  if (NumTags() > available)
    throw InputError("", "/tags",
                     std::to_string(cols_) + "x" + std::to_string(rows_) +
                         " tags; expected at most " + std::to_string(available) + " for family " +
                         name + (first_id_ > 0 ? " from id " + std::to_string(first_id_) : ""));
  if (spec_.Has("min_corners")) spec_.GetInt("min_corners", 4);
  if (spec_.Has("min_border_px")) {
    const auto* px = std::get_if<double>(&spec_.values.at("min_border_px"));
    if (!px || !std::isfinite(*px) || *px < 0)
      throw InputError("", "/min_border_px", "expected a distance in pixels >= 0");
  }
  // Written back explicitly, so an observation file says what was printed.
  spec_.values["family"] = name;
  spec_.values["border_bits"] = static_cast<double>(border_bits_);

  gap_m_ = spacing_ * tag_m_;
  pitch_m_ = tag_m_ + gap_m_;
  bit_m_ = tag_m_ / (family_.bits + 2 * border_bits_);
  const int point_cols = 2 * cols_, point_rows = 2 * rows_;
  points_.reserve(static_cast<std::size_t>(point_cols) * point_rows);
  for (int r = 0; r < point_rows; ++r) {
    for (int c = 0; c < point_cols; ++c) {
      const double X = (c / 2) * pitch_m_ + (c % 2) * tag_m_;
      const double Y = (r / 2) * pitch_m_ + (r % 2) * tag_m_;
      points_.push_back({r * point_cols + c, Eigen::Vector3d(X, -Y, 0.0)});
    }
  }
}

Eigen::AlignedBox2d AprilGridTarget::Extent() const {
  // Outer black squares span X in [-g, cols·p], Y in [-g, rows·p]; one more
  // gap of white around them. y = -Y.
  return Eigen::AlignedBox2d(Eigen::Vector2d(-2 * gap_m_, -(rows_ * pitch_m_ + gap_m_)),
                             Eigen::Vector2d(cols_ * pitch_m_ + gap_m_, 2 * gap_m_));
}

double AprilGridTarget::Albedo(double x_m, double y_m) const {
  // Kalibr coordinates shifted by one gap, so that the black square at gap
  // crossing (i, j) covers [i·p, i·p + g] × [j·p, j·p + g] and tag (i, j)
  // covers [i·p + g, (i+1)·p]².
  const double u = x_m + gap_m_, v = -y_m + gap_m_;
  const double fi = std::floor(u / pitch_m_), fj = std::floor(v / pitch_m_);
  if (fi < 0 || fj < 0 || fi > cols_ || fj > rows_) return 1.0;
  const int i = static_cast<int>(fi), j = static_cast<int>(fj);
  const double lu = u - i * pitch_m_, lv = v - j * pitch_m_;
  const bool gap_u = lu < gap_m_, gap_v = lv < gap_m_;
  if (gap_u && gap_v) return 0.0;  // black square at a gap crossing
  if (gap_u || gap_v || i == cols_ || j == rows_) return 1.0;
  // Inside tag (i, j): cell column from the left, row from the top of the
  // upright tag (Kalibr's Y runs up).
  const int n = family_.bits + 2 * border_bits_;
  const int c = std::clamp(static_cast<int>((lu - gap_m_) / bit_m_), 0, n - 1);
  const int r = std::clamp(static_cast<int>((pitch_m_ - lv) / bit_m_), 0, n - 1);
  if (c < border_bits_ || r < border_bits_ || c >= n - border_bits_ || r >= n - border_bits_)
    return 0.0;
  const auto& code = family_.codes[static_cast<std::size_t>(first_id_ + j * cols_ + i)];
  return code[static_cast<std::size_t>(r - border_bits_) * family_.bits + (c - border_bits_)];
}

std::array<int, 4> AprilGridTarget::TagCornerIds(int tag_id) const {
  const int i = tag_id % cols_, j = tag_id / cols_;
  const int stride = 2 * cols_;
  const int bottom_left = 2 * j * stride + 2 * i;
  return {bottom_left, bottom_left + 1, bottom_left + stride + 1, bottom_left + stride};
}

}  // namespace handeye
