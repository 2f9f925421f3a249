// SPDX-License-Identifier: GPL-2.0-or-later
// Intrinsics through the command line on a rendered cell with robot pose
// error: factory values 1 % off warned about and refined, a camera given none
// estimated, the refined values written so they can be fed back, the report
// drawn through them.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "projected_cell.h"
#include "support/test_support.h"

using namespace handeye;

TEST_CASE("calibrate --refine-intrinsics on a rendered cell with intrinsics 1 % off", "[cli][intrinsics]") {
  const std::string dir = test::TempDir("intrinsics_cli");
  std::string out;
  REQUIRE(test::RunHandeye("simulate " + dir + "/sim --cell small --cameras 3 --poses 24 --seed 11 "
                           "--pose-noise-mm 0.1 --pose-noise-deg 0.01 --image-size 1280x720",
                           &out) == 0);
  REQUIRE(test::RunHandeye("detect " + dir + "/sim/dataset.json -o " + dir + "/obs.json", &out) == 0);
  nlohmann::json obs = nlohmann::json::parse(test::ReadText(dir + "/obs.json"));
  int k = 0;
  for (auto& camera : obs["cameras"]) {
    const double s = k++ % 2 == 0 ? 1.0 : -1.0;
    camera["intrinsics"]["fx"] = camera["intrinsics"]["fx"].get<double>() * (1.0 + 0.01 * s);
    camera["intrinsics"]["fy"] = camera["intrinsics"]["fy"].get<double>() * (1.0 + 0.01 * s);
    camera["intrinsics"]["cx"] = camera["intrinsics"]["cx"].get<double>() + 3.0 * s;
  }
  test::WriteText(dir + "/factory.json", obs.dump());
  const std::string truth = dir + "/sim/ground_truth.json";

  REQUIRE(test::RunHandeye("calibrate " + dir + "/obs.json -o " + dir + "/exact.json", &out) == 0);
  const double exact_mm = test::MeanCameraErrorMm(dir + "/exact.json", truth);
  REQUIRE(test::RunHandeye("calibrate " + dir + "/factory.json -o " + dir + "/off.json", &out) == 0);
  CHECK_THAT(out, Catch::Contains("the images suggest fx, fy") && Catch::Contains("--refine-intrinsics focal"));
  const double off_mm = test::MeanCameraErrorMm(dir + "/off.json", truth);

  REQUIRE(test::RunHandeye("calibrate " + dir + "/factory.json -o " + dir + "/refined.json "
                           "--refine-intrinsics focal,principal_point --cross-validate --report " + dir + "/report",
                           &out) == 0);
  CHECK_THAT(out, !Catch::Contains("the images suggest"));
  const double refined_mm = test::MeanCameraErrorMm(dir + "/refined.json", truth);
  INFO("true intrinsics " << exact_mm << " mm, 1 % off " << off_mm << " mm, refined " << refined_mm << " mm");
  CHECK(off_mm > 5.0);
  CHECK(refined_mm < 0.2 * off_mm);
  const std::string html = test::ReadText(dir + "/report/index.html");
  CHECK_THAT(html, Catch::Contains("<h3>Intrinsics</h3>") && Catch::Contains("refined ± 1σ"));
  CHECK_THAT(html, Catch::Contains("How well each camera is known") && Catch::Contains("Held out"));
  CHECK_THAT(out, Catch::Contains("held out: RMS"));

  // The refined intrinsics are in the dataset's form: fed back, the check is quiet.
  const nlohmann::json refined = nlohmann::json::parse(test::ReadText(dir + "/refined.json"));
  for (auto& camera : obs["cameras"]) {
    const auto& r = refined["cameras"][camera["name"].get<std::string>()];
    REQUIRE(r.contains("intrinsics_sigma"));
    CHECK(r["intrinsics_refined"].size() == 4);
    camera["intrinsics"] = r["intrinsics"];
    camera["distortion"] = r["distortion"];
  }
  test::WriteText(dir + "/fed_back.json", obs.dump());
  REQUIRE(test::RunHandeye("calibrate " + dir + "/fed_back.json -o " + dir + "/again.json", &out) == 0);
  CHECK_THAT(out, !Catch::Contains("the images suggest"));

  // Without intrinsics at all: estimated from the views.
  for (auto& camera : obs["cameras"]) {
    camera.erase("intrinsics");
    camera.erase("distortion");
  }
  test::WriteText(dir + "/none.json", obs.dump());
  REQUIRE(test::RunHandeye("calibrate " + dir + "/none.json -o " + dir + "/none_result.json", &out) == 0);
  CHECK_THAT(out, Catch::Contains("has no intrinsics: started from"));
  const double none_mm = test::MeanCameraErrorMm(dir + "/none_result.json", truth);
  INFO("without intrinsics " << none_mm << " mm");
  CHECK(none_mm < 0.2 * off_mm);
  // Bad lists exit 2 naming the flag.
  CHECK(test::RunHandeye("calibrate " + dir + "/obs.json -o " + dir + "/x.json --refine-intrinsics focus", &out) ==
        2);
  CHECK_THAT(out, Catch::Contains("--refine-intrinsics") && Catch::Contains("'focus'"));
}
