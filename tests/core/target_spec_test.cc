// SPDX-License-Identifier: GPL-2.0-or-later
// TargetSpec's typed getters (core/src/target_spec.cc): each takes what it
// documents and refuses the rest with the key's JSON path and what was
// expected, never falling back to a default silently.
#include "handeye/core/target_spec.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>

#include "handeye/core/error.h"
#include "support/input_error.h"

using namespace handeye;

namespace {

TargetSpec CheckerboardSpec() {
  TargetSpec spec;
  spec.type = "checkerboard";
  spec.values["square_size_m"] = 0.04;
  spec.values["inner_corners"] = std::vector<double>{9, 6};
  spec.values["marker_ratio"] = 0.75;
  spec.values["dictionary"] = std::string("DICT_5X5_100");
  spec.values["count"] = 3.0;
  return spec;
}

}  // namespace

TEST_CASE("TargetSpec's getters read what they document", "[target_spec]") {
  const TargetSpec spec = CheckerboardSpec();
  CHECK(spec.Has("square_size_m"));
  CHECK_FALSE(spec.Has("square_size"));
  CHECK(spec.GetPositive("square_size_m") == 0.04);
  CHECK(spec.GetFraction("marker_ratio") == 0.75);
  CHECK(spec.GetInt("count", 1) == 3);
  CHECK(spec.GetInt("count", 3) == 3);  // the bound itself is allowed
  CHECK(spec.GetIntPair("inner_corners", 2) == std::array<int, 2>{9, 6});
  CHECK(spec.GetString("dictionary", "x") == "DICT_5X5_100");
  CHECK(spec.GetString("legacy", "false") == "false");  // absent: the documented default
}

TEST_CASE("TargetSpec's getters name the key and what they expected", "[target_spec]") {
  TargetSpec spec = CheckerboardSpec();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();

  // Missing keys name the type too.
  auto missing = test::InputErrorOf([&] { spec.GetPositive("tag_size_m"); });
  CHECK(missing.first == "/tag_size_m");
  CHECK(missing.second == "missing key; expected a positive number for a 'checkerboard' target");

  // A number where it is not one, and numbers out of range.
  CHECK(test::InputErrorOf([&] { spec.GetPositive("dictionary"); }) ==
        std::pair<std::string, std::string>{"/dictionary", "expected a positive number"});
  for (double bad : {0.0, -0.04}) {
    spec.values["square_size_m"] = bad;
    CHECK(test::InputErrorOf([&] { spec.GetPositive("square_size_m"); }).second ==
          "expected a positive number");
  }
  for (double bad : {nan, inf, -inf}) {
    spec.values["square_size_m"] = bad;
    CHECK(test::InputErrorOf([&] { spec.GetPositive("square_size_m"); }).second ==
          "expected a positive number, got NaN/Inf");
  }
  for (double bad : {0.0, 1.0, 1.5, -0.2}) {
    spec.values["marker_ratio"] = bad;
    CHECK(test::InputErrorOf([&] { spec.GetFraction("marker_ratio"); }).second ==
          "expected a number between 0 and 1");
  }

  // Integers: whole, at least the bound, not absurd.
  for (double bad : {2.5, 0.0, 1e7}) {
    spec.values["count"] = bad;
    INFO(bad);
    CHECK(test::InputErrorOf([&] { spec.GetInt("count", 1); }) ==
          std::pair<std::string, std::string>{"/count", "expected an integer >= 1"});
  }
  spec.values["count"] = std::vector<double>{3};
  CHECK(test::InputErrorOf([&] { spec.GetInt("count", 1); }).second == "expected an integer >= 1");

  // Pairs: exactly two, each checked, the bad element named by its index.
  spec.values["inner_corners"] = std::vector<double>{9, 6, 4};
  CHECK(test::InputErrorOf([&] { spec.GetIntPair("inner_corners", 2); }) ==
        std::pair<std::string, std::string>{"/inner_corners", "expected two integers >= 2"});
  spec.values["inner_corners"] = 9.0;
  CHECK(test::InputErrorOf([&] { spec.GetIntPair("inner_corners", 2); }).first == "/inner_corners");
  spec.values["inner_corners"] = std::vector<double>{9, 1};
  CHECK(test::InputErrorOf([&] { spec.GetIntPair("inner_corners", 2); }) ==
        std::pair<std::string, std::string>{"/inner_corners/1", "expected two integers >= 2"});
  spec.values["inner_corners"] = std::vector<double>{nan, 6};
  CHECK(test::InputErrorOf([&] { spec.GetIntPair("inner_corners", 2); }).first ==
        "/inner_corners/0");
  spec.values["inner_corners"] = std::vector<double>{9, 6.5};
  CHECK(test::InputErrorOf([&] { spec.GetIntPair("inner_corners", 2); }).first ==
        "/inner_corners/1");

  // A string where it is not one: no fallback.
  spec.values["dictionary"] = 5.0;
  CHECK(test::InputErrorOf([&] { spec.GetString("dictionary", "DICT_4X4_50"); }) ==
        std::pair<std::string, std::string>{"/dictionary", "expected a string"});
}

TEST_CASE("TargetSpec refuses keys its target does not know, naming the ones it does",
          "[target_spec]") {
  const TargetSpec spec = CheckerboardSpec();
  CHECK_NOTHROW(spec.RejectUnknownKeys(
      {"square_size_m", "inner_corners", "marker_ratio", "dictionary", "count", "extra"}));
  const auto error = test::InputErrorOf([&] {
    spec.RejectUnknownKeys({"square_size_m", "inner_corners", "dictionary"});
  });
  // The first unknown key in the map's order.
  CHECK(error.first == "/count");
  CHECK(error.second ==
        "unknown key for a 'checkerboard' target; expected only: type, square_size_m, "
        "inner_corners, dictionary");
  TargetSpec empty;
  empty.type = "charuco";
  CHECK_NOTHROW(empty.RejectUnknownKeys({}));
}
