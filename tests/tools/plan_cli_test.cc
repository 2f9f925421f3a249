// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye plan` and `handeye simulate --poses-file`: a plan made from a
// simulated cell renders exactly the poses it lists, from the JSON plan or
// its CSV; a goal out of reach exits 3 with the best σ reachable.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "handeye/io/dataset_json.h"
#include "handeye/io/plan_json.h"
#include "support/test_support.h"

using namespace handeye;

namespace {

const char* kScene = "--cell small --cameras 2 --image-size 1280x720 --seed 4";

/// A simulated cell with its handeye-cell/1, planned with `plan_args`.
std::string SimulateAndPlan(const std::string& name, const std::string& plan_args, int* plan_exit,
                            std::string* output) {
  const std::string dir = test::TempDir(name);
  REQUIRE(test::RunHandeye("simulate " + dir + "/sampled " + kScene + " --poses 2 --write-cell " + dir +
                               "/cell.json --quiet",
                           output) == 0);
  *plan_exit = test::RunHandeye("plan " + dir + "/cell.json -o " + dir + "/plan.json " + plan_args, output);
  return dir;
}

}  // namespace

TEST_CASE("simulate --poses-file renders exactly the planned poses, from the plan or its CSV", "[plan][simulate]") {
  std::string output;
  int exit = 0;
  const std::string dir = SimulateAndPlan("plan_render", "--poses 4 --candidates 600", &exit, &output);
  INFO(output);
  REQUIRE(exit == 0);
  CHECK_THAT(output, Catch::Contains("4 poses from"));
  const std::vector<PoseRow> planned = ReadPoseFile(dir + "/plan.json");
  REQUIRE(planned.size() == 4);
  REQUIRE(std::filesystem::is_regular_file(dir + "/plan.csv"));
  {
    // What holds each camera's σ back, for the same poses, at most the σ itself.
    const nlohmann::json plan = nlohmann::json::parse(test::ReadText(dir + "/plan.json"));
    const nlohmann::json& last = plan["poses"].back()["sigma_after"];
    REQUIRE(plan["sigma_limits"].size() == last.size());
    for (const auto& [name, sigma] : last.items()) {
      const double position_mm = sigma["position_mm"].get<double>();
      CHECK(plan["sigma_limits"][name]["intrinsics_exact_mm"].get<double>() <=
            position_mm * (1 + 1e-9));
      CHECK(plan["sigma_limits"][name]["robot_exact_mm"].get<double>() <= position_mm * (1 + 1e-9));
      CHECK(plan["sigma_limits"][name]["robot_exact_mm"].get<double>() > 0);
    }
  }
  const GroundTruth sampled = LoadGroundTruth(dir + "/sampled/ground_truth.json");
  for (const std::string file : {"plan.json", "plan.csv"}) {
    INFO(file);
    const std::string out = dir + "/from_" + file;
    REQUIRE(test::RunHandeye("simulate " + out + " " + kScene + " --poses-file " + dir + "/" + file + " --quiet",
                             &output) == 0);
    const GroundTruth truth = LoadGroundTruth(out + "/ground_truth.json");
    REQUIRE(truth.poses.size() == planned.size());
    for (size_t j = 0; j < planned.size(); ++j)
      CHECK((truth.poses[j].T_base_ee_true.matrix() - planned[j].T_base_ee.matrix()).norm() < 1e-8);
    // The same cell: the cameras do not depend on the poses.
    for (const auto& [name, T] : sampled.T_cam) CHECK(truth.T_cam.at(name).isApprox(T, 1e-12));
    // Each planned pose is seen by the cameras the plan says.
    const nlohmann::json plan = nlohmann::json::parse(test::ReadText(dir + "/plan.json"));
    for (size_t j = 0; j < planned.size(); ++j)
      for (const auto& camera : plan["poses"][j]["cameras"])
        CHECK(truth.poses[j].points_px.count(camera.get<std::string>()) == 1);
  }
}

TEST_CASE("plan exits 3 with the best sigma reachable when the goal is out of reach", "[plan]") {
  std::string output;
  int exit = 0;
  SimulateAndPlan("plan_goal", "--goal-mm 0.0001 --poses 3 --candidates 300", &exit, &output);
  CHECK(exit == 3);
  CHECK_THAT(output, Catch::Contains("the goal of 0.0001 mm is not reached within 3 poses: the best reachable is"));
}

TEST_CASE("simulate: --poses-file and --poses do not go together; a bad pose file names itself", "[plan][simulate]") {
  const std::string dir = test::TempDir("poses_file_bad");
  test::WriteText(dir + "/poses.json", R"({"poses": [{"id": "1", "T_base_ee": [[1, 0, 0, 0.5]]}]})");
  std::string output;
  CHECK(test::RunHandeye("simulate " + dir + "/a --poses 3 --poses-file " + dir + "/poses.json", &output) != 0);
  CHECK_THAT(output, Catch::Contains("--poses"));
  CHECK(test::RunHandeye("simulate " + dir + "/b --poses-file " + dir + "/poses.json", &output) == 2);
  CHECK_THAT(output, Catch::Contains("poses.json"));
  CHECK_THAT(output, Catch::Contains("/poses/0/T_base_ee"));
}

TEST_CASE("advise names the cameras above the goal and proposes the next poses, from a capture or its result",
          "[plan][advise]") {
  const std::string dir = test::TempDir("advise_cli");
  std::string output;
  REQUIRE(test::RunHandeye("simulate " + dir + "/capture " + kScene + " --poses 8 --quiet", &output) == 0);
  REQUIRE(test::RunHandeye("detect " + dir + "/capture/dataset.json -o " + dir + "/obs.json --quiet", &output) == 0);
  INFO(output);
  REQUIRE(test::RunHandeye("advise " + dir + "/obs.json --poses 2 --goal-mm 0.001 --candidates 500 -o " + dir +
                               "/next.json",
                           &output) == 0);
  CHECK_THAT(output, Catch::Contains("above the goal of 0.001 mm: cam0 cam1"));
  CHECK_THAT(output, Catch::Contains("what to capture next:"));
  CHECK(ReadPoseFile(dir + "/next.json").size() == 2);
  CHECK(std::filesystem::is_regular_file(dir + "/next.csv"));
  REQUIRE(test::RunHandeye("calibrate " + dir + "/obs.json -o " + dir + "/result.json", &output) == 0);
  REQUIRE(test::RunHandeye("advise " + dir + "/result.json --poses 1 --candidates 500", &output) == 0);
  CHECK_THAT(output, Catch::Contains("what to capture next:"));
}
