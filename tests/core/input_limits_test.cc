// SPDX-License-Identifier: GPL-2.0-or-later
// Caps on declared board sizes (core/input_limits.h): a checkerboard declared
// 20000 x 20000 asked for 12.5 GB of points and ran for minutes, 100000 x
// 100000 ended in std::bad_alloc; a ChArUco board allocated its squares
// before checking them against its dictionary.
#include "handeye/core/input_limits.h"

#include <catch2/catch.hpp>
#include <cstdlib>

#include "handeye/core/charuco.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/error.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;

TargetSpec Checkerboard(double cols, double rows) {
  TargetSpec spec;
  spec.type = "checkerboard";
  spec.values["inner_corners"] = std::vector<double>{cols, rows};
  spec.values["square_size_m"] = 0.01;
  return spec;
}

TargetSpec Charuco(double cols, double rows) {
  TargetSpec spec;
  spec.type = "charuco";
  spec.values["squares"] = std::vector<double>{cols, rows};
  spec.values["square_size_m"] = 0.01;
  spec.values["marker_size_m"] = 0.007;
  spec.values["dictionary"] = std::string("ONE");
  return spec;
}

MarkerCodebook OneMarker() {
  MarkerCodebook book;
  book.name = "ONE";
  book.bits = 3;
  book.codes.push_back({1, 0, 0, 0, 0, 0, 0, 0, 0});
  return book;
}

template <typename Make>
std::string InputErrorText(Make&& make) {
  try {
    make();
  } catch (const InputError& e) {
    return e.json_path() + ": " + e.expected();
  }
  return "";
}

// Sets an environment variable for one scope.
struct ScopedEnvironment {
  ScopedEnvironment(const char* name, const char* value) : name(name) { setenv(name, value, 1); }
  ~ScopedEnvironment() { unsetenv(name); }
  const char* name;
};

TEST_CASE("A board of more target points than the cap is refused before its points are allocated",
          "[core][target][limits]") {
  unsetenv("HANDEYE_MAX_TARGET_POINTS");
  for (const double side : {20000.0, 100000.0}) {
    INFO(side);
    const std::string error = InputErrorText([&] { CheckerboardTarget target(Checkerboard(side, side)); });
    CHECK_THAT(error, Contains("/inner_corners: "));
    CHECK_THAT(error,
               Contains("target points; expected at most 20000 (raise it with --max-target-points or HANDEYE_MAX_TARGET_POINTS"));
    CHECK_THAT(InputErrorText([&] { CharucoTarget target(Charuco(side, side), OneMarker()); }),
               Contains("/squares: ") && Contains("expected at most 20000"));
  }
  CHECK_THAT(InputErrorText([] { CheckerboardTarget target(30000, 2, 0.01); }),
             Contains("60000 target points"));
  // 141 x 141 = 19 881 corners is within the default.
  CHECK(CheckerboardTarget(Checkerboard(141, 141)).Points().size() == 19881);
  CHECK(kDefaultMaxTargetPoints == 20000);
}

TEST_CASE("HANDEYE_MAX_TARGET_POINTS raises or lowers the cap and must be a positive integer",
          "[core][target][limits]") {
  {
    ScopedEnvironment lower("HANDEYE_MAX_TARGET_POINTS", "100");
    CHECK_THAT(InputErrorText([] { CheckerboardTarget target(Checkerboard(11, 10)); }),
               Contains("11 x 10 = 110 target points; expected at most 100"));
    CHECK(CheckerboardTarget(Checkerboard(10, 10)).Points().size() == 100);
  }
  {
    ScopedEnvironment raise("HANDEYE_MAX_TARGET_POINTS", "4e4");
    CHECK(CheckerboardTarget(Checkerboard(200, 200)).Points().size() == 40000);
  }
  for (const char* bad : {"0", "-5", "lots", "1.5", "1e300"}) {
    INFO(bad);
    ScopedEnvironment wrong("HANDEYE_MAX_TARGET_POINTS", bad);
    CHECK_THAT(
        InputErrorText([] { CheckerboardTarget target(Checkerboard(7, 4)); }),
        Contains("environment variable HANDEYE_MAX_TARGET_POINTS: expected a positive integer"));
  }
}

TEST_CASE(
    "Image sizes above HANDEYE_MAX_IMAGE_PIXELS are refused, naming the file and the variable",
    "[core][limits]") {
  unsetenv("HANDEYE_MAX_IMAGE_PIXELS");
  CHECK(MaxImagePixels() == 200000000);
  RequireImagePixelsWithinLimit(16384, 12207, "a.png", "");  // 199 999 488 px
  try {
    RequireImagePixelsWithinLimit(65536, 65536, "big.png", "/cameras/0/image_size");
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.file() == "big.png");
    CHECK(e.json_path() == "/cameras/0/image_size");
    CHECK_THAT(e.what(),
               Contains("65536 x 65536 = 4294967296 pixels; expected at most 200000000 per image "
                        "(raise it with --max-image-pixels or HANDEYE_MAX_IMAGE_PIXELS"));
  }
  ScopedEnvironment raise("HANDEYE_MAX_IMAGE_PIXELS", "5000000000");
  RequireImagePixelsWithinLimit(65536, 65536, "big.png", "");
}

}  // namespace
}  // namespace handeye
