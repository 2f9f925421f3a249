// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye check` never says "nothing moved" (exit 0) when it could not tell:
// a camera without new views and a capture without any are `not_assessed`
// (exit 3); a moved camera still wins (exit 4), and the suggested command is
// one that runs.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "handeye/io/dataset_json.h"
#include "projected_cell.h"
#include "support/test_support.h"

using namespace handeye;
using Catch::Matchers::Contains;

namespace {

// ProjectedSmallCell (a later capture with `pose_seed`) saved to `path`,
// without the views of `drop_camera`.
void SaveCapture(const std::string& path, std::uint64_t pose_seed, bool bumped, const std::string& drop_camera) {
  SyntheticScene scene = test::ProjectedSmallCell(8, pose_seed, bumped);
  std::vector<Observation> kept;
  for (const Observation& view : scene.dataset.observations)
    if (view.camera != drop_camera) kept.push_back(view);
  scene.dataset.observations = kept;
  SaveObservations(scene.dataset, path);
}

}  // namespace

TEST_CASE("check exits 3 with not_assessed for a camera it could not assess", "[cli][drift]") {
  const std::string dir = test::TempDir("check_cannot_tell_cli");
  std::string out;
  SaveCapture(dir + "/calibration.json", 0, false, "");
  REQUIRE(test::RunHandeye("calibrate " + dir + "/calibration.json -o " + dir + "/result.json -q",
                           &out) == 0);
  const std::string check = "check " + dir + "/result.json ";

  SaveCapture(dir + "/later.json", 99, false, "");
  CHECK(test::RunHandeye(check + dir + "/later.json", &out) == 0);

  // cam1 turned away: no view of the target in the new data.
  SaveCapture(dir + "/no_cam1.json", 99, false, "cam1");
  CHECK(test::RunHandeye(check + dir + "/no_cam1.json -o " + dir + "/no_cam1_check.json", &out) ==
        3);
  CHECK_THAT(out, Contains("not assessed (the new data cannot tell whether they moved): cam1"));
  const nlohmann::json written = nlohmann::json::parse(test::ReadText(dir + "/no_cam1_check.json"));
  CHECK(written["cameras"]["cam0"]["verdict"] == "ok");
  CHECK(written["cameras"]["cam1"]["verdict"] == "not_assessed");
  CHECK_THAT(written["cameras"]["cam1"]["reason"].get<std::string>(), Contains("not seen"));
  CHECK_FALSE(written["cameras"]["cam1"].contains("moved_mm"));

  // No views at all.
  SaveCapture(dir + "/none.json", 99, false, "cam0");
  nlohmann::json none = nlohmann::json::parse(test::ReadText(dir + "/none.json"));
  none["observations"] = nlohmann::json::array();
  test::WriteText(dir + "/none.json", none.dump());
  CHECK(test::RunHandeye(check + dir + "/none.json", &out) == 3);
  CHECK_THAT(out, Contains("cam0, cam1"));

  // A moved camera wins over one not assessed, and the command it suggests
  // names the data and holds no camera it could not check.
  SaveCapture(dir + "/knocked.json", 99, true, "cam1");
  CHECK(test::RunHandeye(check + dir + "/knocked.json", &out) == 4);
  INFO(out);
  CHECK_THAT(out, Contains("`handeye calibrate " + dir + "/knocked.json -o NEW.json`"));
  CHECK_THAT(out, !Contains("--keep-cameras"));
  CHECK_THAT(out, !Contains("DATASET"));
  SaveCapture(dir + "/knocked_both.json", 99, true, "");
  CHECK(test::RunHandeye(check + dir + "/knocked_both.json", &out) == 4);
  CHECK_THAT(out, Contains("`handeye calibrate " + dir + "/knocked_both.json -o NEW.json --from " +
                           dir + "/result.json --keep-cameras cam1`"));
}
