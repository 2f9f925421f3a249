// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/charuco.h"

#include <algorithm>
#include <cmath>

#include "handeye/core/error.h"
#include "handeye/core/input_limits.h"

namespace handeye {

CharucoTarget::CharucoTarget(const TargetSpec& spec, MarkerCodebook dictionary)
    : spec_(spec), dictionary_(std::move(dictionary)) {
  spec.RejectUnknownKeys(
      {"squares", "square_size_m", "marker_size_m", "dictionary", "min_corners", "layout"});
  const auto squares = spec.GetIntPair("squares", 2);
  squares_x_ = squares[0];
  squares_y_ = squares[1];
  square_m_ = spec.GetPositive("square_size_m");
  marker_m_ = spec.GetPositive("marker_size_m");
  if (!(marker_m_ < square_m_))
    throw InputError("", "/marker_size_m",
                     "expected a marker smaller than its square (square_size_m)");
  if (!spec.Has("dictionary"))
    throw InputError("", "/dictionary",
                     "missing key; expected an OpenCV dictionary name such as DICT_5X5_100");
  const std::string name = spec.GetString("dictionary", "");
  if (name != dictionary_.name || !dictionary_.Valid())
    throw InputError(
        "", "/dictionary",
        "expected the code book of dictionary '" + name + "', got '" + dictionary_.name + "'");
  if (spec.Has("min_corners")) spec.GetInt("min_corners", 4);
  margin_m_ = 0.5 * (square_m_ - marker_m_);
  RequireTargetPointsWithinLimit(squares_x_ - 1, squares_y_ - 1, "/squares");
  const std::string layout = spec.GetString("layout", "opencv");
  if (layout != "opencv" && layout != "legacy")
    throw InputError(
        "", "/layout",
        "expected \"opencv\" (OpenCV 4.6 and later, the default) or \"legacy\" (boards "
        "printed by OpenCV before 4.6); got '" +
            layout + "'");
  legacy_ = layout == "legacy";
  // Before OpenCV 4.6 the board was laid out from its bottom-left square,
  // which was black: with an even number of rows the top-left one is white.
  const int black_parity = legacy_ && squares_y_ % 2 == 0 ? 1 : 0;

  // Markers fill the white squares row by row, as CharucoBoard::create does.
  square_marker_.assign(static_cast<std::size_t>(squares_x_) * squares_y_, -1);
  for (int b = 0; b < squares_y_; ++b) {
    for (int a = 0; a < squares_x_; ++a) {
      if ((a + b) % 2 == black_parity) continue;
      square_marker_[static_cast<std::size_t>(b) * squares_x_ + a] = NumMarkers();
      marker_square_.push_back({a, b});
    }
  }
  if (NumMarkers() > static_cast<int>(dictionary_.codes.size()))
    throw InputError("", "/squares",
                     "a " + std::to_string(squares_x_) + "x" + std::to_string(squares_y_) +
                         " board needs " + std::to_string(NumMarkers()) +
                         " markers; expected at most " + std::to_string(dictionary_.codes.size()) +
                         " for " + name + " (use a larger dictionary)");

  const int cols = squares_x_ - 1, rows = squares_y_ - 1;
  points_.reserve(static_cast<std::size_t>(cols) * rows);
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < cols; ++x)
      points_.push_back(
          {y * cols + x, Eigen::Vector3d((x + 1) * square_m_, (y + 1) * square_m_, 0.0)});
}

Eigen::AlignedBox2d CharucoTarget::Extent() const {
  return Eigen::AlignedBox2d(
      Eigen::Vector2d(-margin_m_, -margin_m_),
      Eigen::Vector2d(squares_x_ * square_m_ + margin_m_, squares_y_ * square_m_ + margin_m_));
}

double CharucoTarget::Albedo(double x_m, double y_m) const {
  if (!(x_m >= 0 && y_m >= 0 && x_m < squares_x_ * square_m_ && y_m < squares_y_ * square_m_))
    return 1.0;  // margin
  // min(): x_m / L can round up to squares_x_ just below the board's edge.
  const int a = std::min(static_cast<int>(x_m / square_m_), squares_x_ - 1);
  const int b = std::min(static_cast<int>(y_m / square_m_), squares_y_ - 1);
  const int marker = square_marker_[static_cast<std::size_t>(b) * squares_x_ + a];
  if (marker < 0) return 0.0;
  const double u = x_m - a * square_m_ - margin_m_;
  const double v = y_m - b * square_m_ - margin_m_;
  if (!(u >= 0 && v >= 0 && u < marker_m_ && v < marker_m_)) return 1.0;  // white square
  const int n = dictionary_.bits;
  const double cell_m = marker_m_ / (n + 2);
  const int c = std::min(static_cast<int>(u / cell_m), n + 1);
  const int r = std::min(static_cast<int>(v / cell_m), n + 1);
  if (c == 0 || r == 0 || c == n + 1 || r == n + 1) return 0.0;  // the marker's black border
  return dictionary_.codes[marker][static_cast<std::size_t>(r - 1) * n + (c - 1)];
}

int CharucoTarget::MarkerInSquare(int a, int b) const {
  if (a < 0 || b < 0 || a >= squares_x_ || b >= squares_y_) return -1;
  return square_marker_[static_cast<std::size_t>(b) * squares_x_ + a];
}

std::array<Eigen::Vector3d, 4> CharucoTarget::MarkerCorners(int id) const {
  const auto [a, b] = marker_square_.at(static_cast<std::size_t>(id));
  const Eigen::Vector3d top_left(a * square_m_ + margin_m_, b * square_m_ + margin_m_, 0.0);
  return {top_left, top_left + Eigen::Vector3d(marker_m_, 0, 0),
          top_left + Eigen::Vector3d(marker_m_, marker_m_, 0),
          top_left + Eigen::Vector3d(0, marker_m_, 0)};
}

std::array<int, 2> CharucoTarget::MarkersAtCorner(int corner_id) const {
  const int cols = squares_x_ - 1;
  const int x = corner_id % cols, y = corner_id / cols;
  // Corner (x, y) touches squares (x..x+1, y..y+1); two of them are white.
  std::array<int, 2> markers{-1, -1};
  int k = 0;
  for (int b = y; b <= y + 1; ++b)
    for (int a = x; a <= x + 1; ++a)
      if (const int m = MarkerInSquare(a, b); m >= 0) markers[k++] = m;
  return markers;
}

}  // namespace handeye
