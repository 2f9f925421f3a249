// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye calibrate` and `handeye evaluate` end to end on a rendered cell,
// and their exit codes for bad input (2) and unsolvable problems (3).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "handeye/core/checkerboard.h"
#include "handeye/core/synthetic.h"
#include "handeye/io/dataset_json.h"
#include "support/test_support.h"

using namespace handeye;

TEST_CASE("calibrate then evaluate a rendered small cell", "[cli][calibrate]") {
  const std::string dir = test::TempDir("calibrate_cli");
  std::string out;
  REQUIRE(test::RunHandeye("simulate " + dir + "/sim --cell small --cameras 3 --poses 10 --seed 4", &out) == 0);
  INFO(out);
  REQUIRE(test::RunHandeye("calibrate " + dir + "/sim/dataset.json -o " + dir + "/result.json", &out) == 0);
  CHECK(out.find("wrote") != std::string::npos);
  REQUIRE(test::RunHandeye("evaluate " + dir + "/result.json " + dir + "/sim/ground_truth.json --json", &out) == 0);
  const nlohmann::json eval = nlohmann::json::parse(out.substr(out.find('{')));
  // Small cell, 3 cameras, 10 poses at 1920x1080: the joint solve lands within
  // a few millimetres (the Cramér–Rao bound here is about a millimetre).
  CHECK(eval["mean_translation_mm"].get<double>() < 5.0);
  CHECK(eval["mean_rotation_deg"].get<double>() < 0.1);
  CHECK(eval["cameras"].size() == 3);
}

TEST_CASE("calibrate exits 2 on bad input and 3 on degenerate motion", "[cli][calibrate]") {
  const std::string dir = test::TempDir("calibrate_cli_errors");
  std::string out;
  CHECK(test::RunHandeye("calibrate " + dir + "/missing.json -o " + dir + "/r.json", &out) == 2);
  CHECK(out.find("missing.json") != std::string::npos);

  // Observations whose robot poses all share one orientation.
  SceneOptions options;
  options.cell = "small";
  options.num_cameras = 2;
  options.num_poses = 8;
  SyntheticScene scene = MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
  std::mt19937_64 rng(1);
  AddProjectedObservations(&scene, 0.1, &rng);
  const std::string obs = dir + "/obs.json";
  SaveObservations(scene.dataset, obs);
  CHECK(test::RunHandeye("calibrate " + obs + " -o " + dir + "/r.json --method nonsense", &out) == 2);
  CHECK(out.find("--method") != std::string::npos);
  REQUIRE(test::RunHandeye("calibrate " + obs + " -o " + dir + "/r.json", &out) == 0);

  for (auto& pose : scene.dataset.poses) pose.T_base_ee.linear() = scene.dataset.poses[0].T_base_ee.rotation();
  SaveObservations(scene.dataset, obs);
  CHECK(test::RunHandeye("calibrate " + obs + " -o " + dir + "/r2.json", &out) == 3);
  CHECK(out.find("degenerate robot motion") != std::string::npos);
}
