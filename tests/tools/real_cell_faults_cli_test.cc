// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye simulate` cells with the faults of real captures, rendered and
// detected, then `handeye calibrate` with default flags: exit 0, the bad views
// named, the error as without them.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <set>

#include "handeye/io/dataset_json.h"
#include "handeye/io/result_json.h"
#include "projected_cell.h"
#include "support/test_support.h"

using namespace handeye;

TEST_CASE("calibrate a rendered cell whose robot records of 4 of 24 poses are swapped", "[cli][robust]") {
  const std::string dir = test::TempDir("faults_swapped");
  std::string out;
  REQUIRE(test::RunHandeye("simulate " + dir + "/sim --cell medium --cameras 4 --poses 24 --seed 7 "
                           "--swap-poses 2 --pose-noise-mm 0.3 --pose-noise-deg 0.03 --visible-only "
                           "--image-size 1280x720",
                           &out) == 0);
  INFO(out);
  std::set<std::string> swapped;
  for (size_t at = out.find("poses "); at != std::string::npos; at = out.find("poses ", at + 1)) {
    // "robot records of poses 0003 and 0017 exchanged"
    if (out.compare(at + 10, 5, " and ") != 0) continue;
    swapped.insert(out.substr(at + 6, 4));
    swapped.insert(out.substr(at + 15, 4));
  }
  REQUIRE(swapped.size() == 4);

  REQUIRE(test::RunHandeye("calibrate " + dir + "/sim/dataset.json -o " + dir + "/result.json", &out) == 0);
  for (const std::string& pose : swapped) CHECK_THAT(out, Catch::Contains("pose " + pose + ": its robot record"));
  const CalibrationResult result = LoadResult(dir + "/result.json");
  int good_dropped = 0;
  for (const ViewResult& view : result.views) {
    INFO(view.pose_id << "/" << view.camera << ": " << view.rejected_because);
    if (swapped.count(view.pose_id)) CHECK_FALSE(view.used);
    else good_dropped += view.used ? 0 : 1;
  }
  CHECK(good_dropped <= 1);

  // The same cell without the swapped poses' views.
  REQUIRE(test::RunHandeye("detect " + dir + "/sim/dataset.json -o " + dir + "/obs.json", &out) == 0);
  nlohmann::json obs = nlohmann::json::parse(test::ReadText(dir + "/obs.json"));
  nlohmann::json kept = nlohmann::json::array();
  for (const auto& view : obs["observations"])
    if (!swapped.count(view["pose"].get<std::string>())) kept.push_back(view);
  obs["observations"] = kept;
  test::WriteText(dir + "/clean.json", obs.dump());
  REQUIRE(test::RunHandeye("calibrate " + dir + "/clean.json -o " + dir + "/clean_result.json", &out) == 0);
  const double error = test::MeanCameraErrorMm(dir + "/result.json", dir + "/sim/ground_truth.json");
  const double clean_error = test::MeanCameraErrorMm(dir + "/clean_result.json", dir + "/sim/ground_truth.json");
  INFO("error " << error << " mm, without the bad views " << clean_error << " mm");
  CHECK(error <= 1.2 * clean_error);
}

TEST_CASE("calibrate a rendered cell with a see-through target", "[cli][robust]") {
  const std::string dir = test::TempDir("faults_glass");
  std::string out;
  REQUIRE(test::RunHandeye("simulate " + dir + "/sim --cell small --cameras 4 --poses 40 --seed 2 "
                           "--see-through --image-size 960x540",
                           &out) == 0);
  INFO(out);
  REQUIRE(test::RunHandeye("calibrate " + dir + "/sim/dataset.json -o " + dir + "/result.json", &out) == 0);
  const CalibrationResult result = LoadResult(dir + "/result.json");
  const GroundTruth truth = LoadGroundTruth(dir + "/sim/ground_truth.json");
  // A view is of the back when the camera is on the target's +z side (truth).
  auto from_behind = [&](const ViewResult& view) {
    for (const auto& pose : truth.poses) {
      if (pose.id != view.pose_id) continue;
      const Eigen::Isometry3d T_cam_target =
          truth.T_cam.at(view.camera).inverse() * pose.T_base_ee_true * truth.T_target;
      return T_cam_target.inverse().translation().z() > 0;
    }
    return false;
  };
  int mirrored = 0, front_dropped = 0;
  for (const ViewResult& view : result.views) {
    INFO(view.pose_id << "/" << view.camera << ": " << view.rejected_because);
    if (!from_behind(view)) {
      front_dropped += view.used ? 0 : 1;
      continue;
    }
    ++mirrored;
    CHECK_FALSE(view.used);
    CHECK_THAT(view.rejected_because, Catch::Contains("seen from behind"));
  }
  CHECK(mirrored >= 1);
  CHECK(front_dropped <= 1);
  CHECK(test::MeanCameraErrorMm(dir + "/result.json", dir + "/sim/ground_truth.json") < 0.2);
}
