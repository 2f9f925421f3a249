// SPDX-License-Identifier: GPL-2.0-or-later
// ChArUco geometry and print with a small hand-made code book (no OpenCV):
// ids, corner positions, which square holds which marker, and the texture.
#include <catch2/catch.hpp>
#include <cmath>

#include "handeye/core/charuco.h"
#include "handeye/core/error.h"

using namespace handeye;

namespace {

// Three-cell markers: code k has cell (r, c) white when bit r·3 + c of k+1
// is set, so every marker differs.
MarkerCodebook TinyDictionary(int count) {
  MarkerCodebook book;
  book.name = "TINY";
  book.bits = 3;
  for (int k = 0; k < count; ++k) {
    std::vector<std::uint8_t> code(9);
    for (int i = 0; i < 9; ++i) code[i] = ((k + 1) >> i) & 1;
    book.codes.push_back(code);
  }
  return book;
}

TargetSpec CharucoSpec(int sx, int sy, double square, double marker) {
  TargetSpec spec;
  spec.type = "charuco";
  spec.values["squares"] = std::vector<double>{double(sx), double(sy)};
  spec.values["square_size_m"] = square;
  spec.values["marker_size_m"] = marker;
  spec.values["dictionary"] = std::string("TINY");
  return spec;
}

std::string CharucoErrorOf(const TargetSpec& spec, const MarkerCodebook& book) {
  try {
    CharucoTarget target(spec, book);
  } catch (const InputError& e) {
    return e.json_path() + ": " + e.expected();
  }
  return "";
}

}  // namespace

TEST_CASE("charuco corners have OpenCV 4.6 ids y*(sx-1)+x at ((x+1)L, (y+1)L)", "[charuco]") {
  const CharucoTarget board(CharucoSpec(5, 4, 0.04, 0.03), TinyDictionary(20));
  REQUIRE(board.Points().size() == 4 * 3);
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 4; ++x) {
      const TargetPoint& p = board.Points()[y * 4 + x];
      CHECK(p.id == y * 4 + x);
      CHECK(p.p_target.x() == Approx((x + 1) * 0.04));
      CHECK(p.p_target.y() == Approx((y + 1) * 0.04));
      CHECK(p.p_target.z() == 0.0);
    }
  }
}

TEST_CASE("charuco markers fill the white squares row by row, square (0, 0) black", "[charuco]") {
  const CharucoTarget board(CharucoSpec(5, 4, 0.04, 0.03), TinyDictionary(20));
  // 5x4 squares: white where a + b is odd, 10 of them.
  CHECK(board.NumMarkers() == 10);
  CHECK(board.MarkerInSquare(0, 0) == -1);
  CHECK(board.MarkerInSquare(1, 0) == 0);
  CHECK(board.MarkerInSquare(3, 0) == 1);
  CHECK(board.MarkerInSquare(0, 1) == 2);
  CHECK(board.MarkerInSquare(2, 1) == 3);
  CHECK(board.MarkerInSquare(4, 1) == 4);
  CHECK(board.MarkerInSquare(4, 3) == 9);
  CHECK(board.MarkerInSquare(3, 3) == -1);
  CHECK(board.MarkerInSquare(5, 0) == -1);
  // Marker 3 in square (2, 1), centred: margin (0.04 - 0.03) / 2.
  const auto corners = board.MarkerCorners(3);
  CHECK(corners[0].x() == Approx(0.085));
  CHECK(corners[0].y() == Approx(0.045));
  CHECK(corners[1].x() == Approx(0.115));  // top-right
  CHECK(corners[1].y() == Approx(0.045));
  CHECK(corners[2].y() == Approx(0.075));  // bottom-right
  CHECK(corners[3].x() == Approx(0.085));  // bottom-left
  // Corner (1, 0) at (0.08, 0.04) touches squares (1..2, 0..1): markers in
  // (1, 0) and (2, 1).
  const auto around = board.MarkersAtCorner(1);
  CHECK(around[0] == 0);
  CHECK(around[1] == 3);
}

TEST_CASE(
    "charuco texture: black squares, white margin, markers with a black border and their bits",
    "[charuco]") {
  const MarkerCodebook book = TinyDictionary(20);
  const CharucoTarget board(CharucoSpec(5, 4, 0.04, 0.03), book);
  const auto extent = board.Extent();
  CHECK(extent.min().x() == Approx(-0.005));
  CHECK(extent.max().x() == Approx(0.205));
  CHECK(extent.max().y() == Approx(0.165));
  CHECK(board.Albedo(-0.002, 0.02) == 1.0);  // margin
  CHECK(board.Albedo(0.02, 0.02) == 0.0);    // square (0, 0)
  CHECK(board.Albedo(0.06, 0.06) == 0.0);    // square (1, 1)
  CHECK(board.Albedo(0.042, 0.02) == 1.0);   // square (1, 0), outside its marker
  // Marker 0 in square (1, 0): cells of 0.03 / 5 = 6 mm from (0.045, 0.005).
  const double cell = 0.006;
  CHECK(board.Albedo(0.045 + 0.5 * cell, 0.005 + 2.5 * cell) == 0.0);  // border column
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      CHECK(board.Albedo(0.045 + (c + 1.5) * cell, 0.005 + (r + 1.5) * cell) ==
            book.codes[0][r * 3 + c]);
  // Marker 4 in square (4, 1).
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      CHECK(board.Albedo(0.165 + (c + 1.5) * cell, 0.045 + (r + 1.5) * cell) ==
            book.codes[4][r * 3 + c]);
}

TEST_CASE("charuco spec errors name the key", "[charuco]") {
  const MarkerCodebook book = TinyDictionary(20);
  CHECK_THAT(CharucoErrorOf(CharucoSpec(5, 4, 0.04, 0.04), book), Catch::Contains("/marker_size_m"));
  CHECK_THAT(CharucoErrorOf(CharucoSpec(1, 4, 0.04, 0.03), book), Catch::Contains("/squares"));
  CHECK_THAT(CharucoErrorOf(CharucoSpec(9, 9, 0.04, 0.03), book), Catch::Contains("needs 40 markers"));
  TargetSpec typo = CharucoSpec(5, 4, 0.04, 0.03);
  typo.values["marker_size"] = 0.03;
  CHECK_THAT(CharucoErrorOf(typo, book), Catch::Contains("/marker_size"));
  TargetSpec other = CharucoSpec(5, 4, 0.04, 0.03);
  other.values["dictionary"] = std::string("DICT_4X4_50");
  CHECK_THAT(CharucoErrorOf(other, book), Catch::Contains("/dictionary"));
  TargetSpec few = CharucoSpec(5, 4, 0.04, 0.03);
  few.values["min_corners"] = 3.0;
  CHECK_THAT(CharucoErrorOf(few, book), Catch::Contains("/min_corners"));
  few.values["min_corners"] = 6.0;
  CHECK(CharucoErrorOf(few, book).empty());
}
