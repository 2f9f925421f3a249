// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye check` on rendered captures of one cell: weeks after calibration,
// 8 new poses; one camera knocked by 5 mm / 0.2°. Exit 4 naming it, 0 when
// none moved; then only that camera recalibrated with the others held.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "handeye/core/evaluation.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/result_json.h"
#include "support/test_support.h"

using namespace handeye;

TEST_CASE("check finds the knocked camera in 8 new rendered poses", "[cli][drift]") {
  const std::string dir = test::TempDir("check_cli");
  const std::string cell = " --cell medium --cameras 4 --seed 21 --pose-noise-mm 0.1 --pose-noise-deg 0.01 "
                           "--quiet";
  std::string out;
  REQUIRE(test::RunHandeye("simulate " + dir + "/calibration --poses 20" + cell, &out) == 0);
  REQUIRE(test::RunHandeye("simulate " + dir + "/later --poses 8 --pose-seed 99" + cell, &out) == 0);
  REQUIRE(test::RunHandeye("simulate " + dir + "/knocked --poses 8 --pose-seed 99 --bump-camera cam1:5:0.2" + cell,
                           &out) == 0);
  REQUIRE(test::RunHandeye("calibrate " + dir + "/calibration/dataset.json -o " + dir + "/result.json", &out) == 0);
  const CalibrationResult calibration = LoadResult(dir + "/result.json");
  for (const CameraResult& c : calibration.cameras) CHECK(c.sigma);

  CHECK(test::RunHandeye("check " + dir + "/result.json " + dir + "/later/dataset.json -o " + dir + "/ok.json",
                         &out) == 0);
  const nlohmann::json ok = nlohmann::json::parse(test::ReadText(dir + "/ok.json"));
  CHECK(ok["format"] == "handeye-check/1");
  for (const auto& [name, c] : ok["cameras"].items()) {
    INFO(name << ": " << c.dump());
    CHECK(c["verdict"] == "ok");
    CHECK(c["moved_mm"].get<double>() < 1.0);
  }

  CHECK(test::RunHandeye("check " + dir + "/result.json " + dir + "/knocked/dataset.json -o " + dir +
                             "/knocked.json",
                         &out) == 4);
  CHECK_THAT(out, Catch::Contains("--keep-cameras cam0,cam2,cam3"));
  const nlohmann::json knocked = nlohmann::json::parse(test::ReadText(dir + "/knocked.json"));
  for (const auto& [name, c] : knocked["cameras"].items()) {
    INFO(name << ": " << c.dump());
    if (name == "cam1") {
      CHECK(c["verdict"] == "moved");
      CHECK(c["moved_mm"].get<double>() > 4.0);
      CHECK(c["moved_mm"].get<double>() < 6.0);
    } else {
      CHECK(c["verdict"] == "ok");
      CHECK(c["moved_mm"].get<double>() < 1.0);
    }
  }

  // The knocked camera alone, the others held at their calibrated poses.
  REQUIRE(test::RunHandeye("calibrate " + dir + "/knocked/dataset.json -o " + dir + "/again.json --from " + dir +
                               "/result.json --keep-cameras cam0,cam2,cam3",
                           &out) == 0);
  const auto errors = EvaluateAgainstTruth(LoadResult(dir + "/again.json"), LoadGroundTruth(dir + "/knocked/ground_truth.json"));
  for (const auto& c : errors.cameras) {
    INFO(c.name << " " << c.translation_mm << " mm");
    CHECK(c.translation_mm < 1.0);
  }
  // Bad uses exit 2.
  CHECK(test::RunHandeye("calibrate " + dir + "/knocked/dataset.json -o " + dir + "/x.json --keep-cameras cam0",
                         &out) == 2);
  CHECK_THAT(out, Catch::Contains("--from"));
  CHECK(test::RunHandeye("calibrate " + dir + "/knocked/dataset.json -o " + dir + "/x.json --from " + dir +
                             "/result.json --keep-cameras cam9",
                         &out) == 2);
  CHECK_THAT(out, Catch::Contains("cam9"));
  CHECK(test::RunHandeye("check " + dir + "/result.json " + dir + "/later/dataset.json --tolerance-mm 0", &out) == 2);
}
