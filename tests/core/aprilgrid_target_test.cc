// SPDX-License-Identifier: GPL-2.0-or-later
// AprilGrid geometry and print against Kalibr's definition, with a small
// hand-made code book (no libapriltag).
#include <catch2/catch.hpp>

#include "handeye/core/aprilgrid.h"
#include "handeye/core/error.h"

using namespace handeye;

namespace {

// 2×2 data cells: code k has cell i white when bit i of k+1 is set.
MarkerCodebook TinyFamily(int count) {
  MarkerCodebook book;
  book.name = "tag36h11";  // the name the spec asks for; the cells are ours
  book.bits = 2;
  for (int k = 0; k < count; ++k) {
    std::vector<std::uint8_t> code(4);
    for (int i = 0; i < 4; ++i) code[i] = ((k + 1) >> i) & 1;
    book.codes.push_back(code);
  }
  return book;
}

TargetSpec AprilGridSpec(int cols, int rows, double size, double spacing) {
  TargetSpec spec;
  spec.type = "aprilgrid";
  spec.values["tags"] = std::vector<double>{double(cols), double(rows)};
  spec.values["tag_size_m"] = size;
  spec.values["tag_spacing"] = spacing;
  return spec;
}

std::string AprilGridErrorOf(const TargetSpec& spec) {
  try {
    AprilGridTarget target(spec, TinyFamily(10));
  } catch (const InputError& e) {
    return e.json_path() + ": " + e.expected();
  }
  return "";
}

}  // namespace

TEST_CASE("aprilgrid points follow Kalibr's index layout, y negated", "[aprilgrid]") {
  // Kalibr: point (c, r) of a 2·cols × 2·rows grid has id r·2·cols + c and
  // lies at X = ⌊c/2⌋(s+g) + (c mod 2)s, Y likewise with r; here y = -Y.
  const double s = 0.08, g = 0.3 * s;
  const AprilGridTarget grid(AprilGridSpec(3, 2, s, 0.3), TinyFamily(10));
  REQUIRE(grid.Points().size() == 6 * 4);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 6; ++c) {
      const TargetPoint& p = grid.Points()[r * 6 + c];
      CHECK(p.id == r * 6 + c);
      CHECK(p.p_target.x() == Approx((c / 2) * (s + g) + (c % 2) * s));
      CHECK(p.p_target.y() == Approx(-((r / 2) * (s + g) + (r % 2) * s)));
    }
  }
  // Kalibr's own picture of a 2×2 grid: tag 0 has corners 0, 1, 5, 4
  // (bottom-left, bottom-right, top-right, top-left); tag 3 has 10, 11, 15, 14.
  const AprilGridTarget two(AprilGridSpec(2, 2, s, 0.3), TinyFamily(10));
  CHECK(two.TagCornerIds(0) == std::array<int, 4>{0, 1, 5, 4});
  CHECK(two.TagCornerIds(1) == std::array<int, 4>{2, 3, 7, 6});
  CHECK(two.TagCornerIds(2) == std::array<int, 4>{8, 9, 13, 12});
  CHECK(two.TagCornerIds(3) == std::array<int, 4>{10, 11, 15, 14});
}

TEST_CASE("aprilgrid print: tag 0 bottom-left and upright, 2-bit border, black corner squares",
          "[aprilgrid]") {
  const double s = 0.06, g = 0.25 * s, b = s / 6;  // 2 data + 2·2 border cells
  const MarkerCodebook book = TinyFamily(10);
  const AprilGridTarget grid(AprilGridSpec(3, 2, s, 0.25), book);
  // Corner squares at the gap crossings touch the tag corners diagonally.
  CHECK(grid.Albedo(-0.5 * g, 0.5 * g) == 0.0);        // below-left of tag 0's bottom-left corner
  CHECK(grid.Albedo(s + 0.5 * g, 0.5 * g) == 0.0);     // between tags 0 and 1, bottom row
  CHECK(grid.Albedo(s + 0.5 * g, -0.5 * s) == 1.0);    // gap between tags 0 and 1
  CHECK(grid.Albedo(0.5 * s, 0.5 * g) == 1.0);         // gap below tag 0
  CHECK(grid.Albedo(0.5 * s, -(s + 0.5 * g)) == 1.0);  // gap between rows
  CHECK(grid.Albedo(-1.5 * g, 0.0) == 1.0);            // margin
  // Tag 0 covers x in [0, s], y in [-s, 0]; its top row of data cells is at
  // the top (most negative y), as the tag is printed upright.
  CHECK(grid.Albedo(0.5 * b, -0.5 * s) == 0.0);  // border
  CHECK(grid.Albedo(1.5 * b, -0.5 * s) == 0.0);  // border, second bit
  for (int tag = 0; tag < 6; ++tag) {
    const double x0 = (tag % 3) * (s + g), y_top = -((tag / 3) * (s + g) + s);
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c)
        CHECK(grid.Albedo(x0 + (2 + c + 0.5) * b, y_top + (2 + r + 0.5) * b) ==
              book.codes[tag][r * 2 + c]);
  }
  // Tag 3 is above tag 0 (row 1, column 0).
  const std::array<int, 4> ids = grid.TagCornerIds(3);
  CHECK(grid.FindPoint(ids[0])->p_target.y() == Approx(-(s + g)));
}

TEST_CASE("aprilgrid with a 1-bit border puts the data one cell further out", "[aprilgrid]") {
  const double s = 0.04, b = s / 4;
  TargetSpec spec = AprilGridSpec(1, 1, s, 0.3);
  spec.values["border_bits"] = 1.0;
  const MarkerCodebook book = TinyFamily(10);
  const AprilGridTarget grid(spec, book);
  CHECK(grid.border_bits() == 1);
  CHECK(grid.Albedo(0.5 * b, -0.5 * s) == 0.0);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c)
      CHECK(grid.Albedo((1 + c + 0.5) * b, -s + (1 + r + 0.5) * b) == book.codes[0][r * 2 + c]);
}

TEST_CASE("aprilgrid accepts Kalibr's key names and writes SPEC's", "[aprilgrid]") {
  TargetSpec kalibr;
  kalibr.type = "aprilgrid";
  kalibr.values["tagCols"] = 6.0;
  kalibr.values["tagRows"] = 4.0;
  kalibr.values["tagSize"] = 0.088;
  kalibr.values["tagSpacing"] = 0.3;
  const AprilGridTarget grid(kalibr, TinyFamily(30));
  CHECK(grid.tags_x() == 6);
  CHECK(grid.tags_y() == 4);
  CHECK(grid.tag_size_m() == 0.088);
  CHECK(grid.tag_spacing() == 0.3);
  const TargetSpec& spec = grid.Spec();
  CHECK(spec.Has("tags"));
  CHECK(spec.Has("tag_size_m"));
  CHECK_FALSE(spec.Has("tagCols"));
  CHECK(spec.GetString("family", "") == "tag36h11");
  CHECK(spec.GetInt("border_bits", 1) == 2);
  const AprilGridTarget same(AprilGridSpec(6, 4, 0.088, 0.3), TinyFamily(30));
  REQUIRE(same.Points().size() == grid.Points().size());
  for (std::size_t i = 0; i < grid.Points().size(); ++i)
    CHECK((same.Points()[i].p_target - grid.Points()[i].p_target).norm() < 1e-15);
}

TEST_CASE("aprilgrid spec errors name the key", "[aprilgrid]") {
  CHECK_THAT(AprilGridErrorOf(AprilGridSpec(4, 3, 0.05, 1.5)), Catch::Contains("/tag_spacing"));
  CHECK_THAT(AprilGridErrorOf(AprilGridSpec(4, 3, -0.05, 0.3)), Catch::Contains("/tag_size_m"));
  CHECK_THAT(AprilGridErrorOf(AprilGridSpec(4, 3, 0.05, 0.3)), Catch::Contains("/tags"));  // 12 tags, 10 codes
  TargetSpec both = AprilGridSpec(2, 2, 0.05, 0.3);
  both.values["tagCols"] = 2.0;
  both.values["tagRows"] = 2.0;
  CHECK_THAT(AprilGridErrorOf(both), Catch::Contains("not both"));
  TargetSpec bits = AprilGridSpec(2, 2, 0.05, 0.3);
  bits.values["border_bits"] = 3.0;
  CHECK_THAT(AprilGridErrorOf(bits), Catch::Contains("/border_bits"));
  TargetSpec family = AprilGridSpec(2, 2, 0.05, 0.3);
  family.values["family"] = std::string("tag25h9");
  CHECK_THAT(AprilGridErrorOf(family), Catch::Contains("/family"));
  TargetSpec border = AprilGridSpec(2, 2, 0.05, 0.3);
  border.values["min_border_px"] = -1.0;
  CHECK_THAT(AprilGridErrorOf(border), Catch::Contains("/min_border_px"));
  TargetSpec typo = AprilGridSpec(2, 2, 0.05, 0.3);
  typo.values["tag_size"] = 0.05;
  CHECK_THAT(AprilGridErrorOf(typo), Catch::Contains("/tag_size"));
}
