// SPDX-License-Identifier: GPL-2.0-or-later
// The help texts point to the documentation the repository ships (docs/),
// not to a specification users do not have.
#include <catch2/catch.hpp>
#include <string>

#include "support/test_support.h"

using Catch::Matchers::Contains;

TEST_CASE("No --help text cites the SPEC; the ones that cite a format cite docs/", "[cli][docs]") {
  std::string out;
  REQUIRE(handeye::test::RunHandeye("--help", &out) == 0);
  CHECK_THAT(out, !Contains("SPEC"));
  for (const char* command : {"simulate", "detect", "calibrate", "report", "evaluate", "check",
                              "export", "import-metric", "import-poses", "target", "plan", "advise"}) {
    INFO(command);
    REQUIRE(handeye::test::RunHandeye(std::string(command) + " --help", &out) == 0);
    CHECK_THAT(out, !Contains("SPEC"));
  }
  REQUIRE(handeye::test::RunHandeye("target --help", &out) == 0);
  CHECK_THAT(out, Contains("docs/formats.md#targets"));
  REQUIRE(handeye::test::RunHandeye("import-poses --help", &out) == 0);
  CHECK_THAT(out, Contains("docs/formats.md"));
  REQUIRE(handeye::test::RunHandeye("plan --help", &out) == 0);
  CHECK_THAT(out, Contains("docs/formats.md"));
}
