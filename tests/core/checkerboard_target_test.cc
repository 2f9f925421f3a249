// SPDX-License-Identifier: GPL-2.0-or-later
// The checkerboard target (core/src/checkerboard.cc) on its own: its corner
// ids and positions, the printed pattern the renderer draws from it (every
// inner corner where four squares of alternating colour meet), the 180°
// ambiguity it warns about, and the values it refuses.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>

#include "handeye/core/checkerboard.h"
#include "handeye/core/error.h"
#include "support/input_error.h"

using namespace handeye;
using Catch::Matchers::Contains;

TEST_CASE("checkerboard corners: id j*cols + i at (i, j) squares, found by id", "[checkerboard]") {
  const CheckerboardTarget board(9, 6, 0.025);
  CHECK(board.Type() == "checkerboard");
  CHECK(board.cols() == 9);
  CHECK(board.rows() == 6);
  CHECK(board.square_size_m() == 0.025);
  const auto& points = board.Points();
  REQUIRE(points.size() == 54);
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 9; ++i) {
      const TargetPoint& p = points[j * 9 + i];
      INFO("corner (" << i << ", " << j << ")");
      CHECK(p.id == j * 9 + i);
      CHECK(p.p_target.isApprox(Eigen::Vector3d(0.025 * i, 0.025 * j, 0.0)));
      REQUIRE(board.FindPoint(p.id) == &p);
    }
  CHECK(board.FindPoint(-1) == nullptr);
  CHECK(board.FindPoint(54) == nullptr);
}

TEST_CASE("checkerboard from its spec: the same board, and the spec it keeps", "[checkerboard]") {
  const CheckerboardTarget made(7, 4, 0.04);
  const TargetSpec& spec = made.Spec();
  CHECK(spec.type == "checkerboard");
  CHECK(spec.GetIntPair("inner_corners", 2) == std::array<int, 2>{7, 4});
  CHECK(spec.GetPositive("square_size_m") == 0.04);
  const CheckerboardTarget read(spec);
  REQUIRE(read.Points().size() == made.Points().size());
  for (size_t k = 0; k < made.Points().size(); ++k) {
    CHECK(read.Points()[k].id == made.Points()[k].id);
    CHECK(read.Points()[k].p_target == made.Points()[k].p_target);
  }
}

TEST_CASE("checkerboard pattern: four squares of alternating colour meet at every inner corner",
          "[checkerboard]") {
  const double s = 0.03;
  const CheckerboardTarget board(5, 4, s);
  const double e = 0.25 * s;  // a quarter square off the corner, inside each of the four squares
  for (const TargetPoint& p : board.Points()) {
    const double x = p.p_target.x(), y = p.p_target.y();
    INFO("corner " << p.id);
    const double a = board.Albedo(x + e, y + e), b = board.Albedo(x - e, y + e),
                 c = board.Albedo(x - e, y - e), d = board.Albedo(x + e, y - e);
    CHECK((a == 0.0 || a == 1.0));
    CHECK(a == c);  // diagonal squares alike
    CHECK(b == d);
    CHECK(a != b);  // neighbours differ
  }
  // The square after corner (0, 0) is black, and so is the one before it:
  // the board's outer squares lie a square beyond the outer corners.
  CHECK(board.Albedo(0.5 * s, 0.5 * s) == 0.0);
  CHECK(board.Albedo(-0.5 * s, -0.5 * s) == 0.0);
  CHECK(board.Albedo(4.5 * s, 3.5 * s) == 1.0);  // past corner (4, 3): 4 + 3 odd, white
  // Beyond the squares: the white margin, a square wide, then nothing printed (white too).
  CHECK(board.Albedo(-1.5 * s, 0.5 * s) == 1.0);
  CHECK(board.Albedo(5.5 * s, 0.5 * s) == 1.0);
  CHECK(board.Albedo(0.5 * s, 4.5 * s) == 1.0);
  CHECK(board.Albedo(100.0, -100.0) == 1.0);
  const Eigen::AlignedBox2d extent = board.Extent();
  CHECK(extent.min().isApprox(Eigen::Vector2d(-2 * s, -2 * s)));
  CHECK(extent.max().isApprox(Eigen::Vector2d(6 * s, 5 * s)));
  for (const TargetPoint& p : board.Points())
    CHECK(extent.contains(Eigen::Vector2d(p.p_target.x(), p.p_target.y())));
}

TEST_CASE("checkerboard: a board that looks the same turned half round is named, with a fix",
          "[checkerboard]") {
  const CheckerboardTarget ambiguous(7, 5, 0.03);
  CHECK(ambiguous.IsAmbiguous());
  const std::vector<std::string> warnings = ambiguous.Warnings();
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Contains("checkerboard 7x5 inner corners is 180-degree ambiguous"));
  CHECK_THAT(warnings[0], Contains("e.g. 7x6"));
  const CheckerboardTarget fine(7, 6, 0.03);
  CHECK_FALSE(fine.IsAmbiguous());
  CHECK(fine.Warnings().empty());
  CHECK(CheckerboardTarget(2, 2, 0.01).IsAmbiguous());
  CHECK_FALSE(CheckerboardTarget(2, 3, 0.01).IsAmbiguous());
}

TEST_CASE("checkerboard: what it refuses, with the key's path", "[checkerboard]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(test::InputErrorOf([] { CheckerboardTarget(1, 5, 0.03); }) ==
        std::pair<std::string, std::string>{"/inner_corners", "expected two integers >= 2"});
  CHECK(test::InputErrorOf([] { CheckerboardTarget(5, 1, 0.03); }).first == "/inner_corners");
  CHECK(test::InputErrorOf([] { CheckerboardTarget(5, 4, 0.0); }) ==
        std::pair<std::string, std::string>{"/square_size_m", "expected a positive number"});
  CHECK(test::InputErrorOf([nan] { CheckerboardTarget(5, 4, nan); }).first == "/square_size_m");
  // A board too large to hold in memory is refused before its points are made.
  CHECK(test::InputErrorOf([] { CheckerboardTarget(100000, 100000, 0.01); }).first ==
        "/inner_corners");

  TargetSpec spec = CheckerboardTarget(5, 4, 0.03).Spec();
  spec.values["square_size"] = 0.03;  // a typo for square_size_m
  CHECK(test::InputErrorOf([&] { CheckerboardTarget{spec}; }) ==
        std::pair<std::string, std::string>{
            "/square_size",
            "unknown key for a 'checkerboard' target; expected only: type, inner_corners, "
            "square_size_m"});
  spec.values.erase("square_size");
  spec.values["inner_corners"] = std::vector<double>{5.5, 4};
  CHECK(test::InputErrorOf([&] { CheckerboardTarget{spec}; }).first == "/inner_corners/0");
  spec.values.erase("inner_corners");
  CHECK_THAT(test::InputErrorOf([&] { CheckerboardTarget{spec}; }).second, Contains("missing key"));
}
