// SPDX-License-Identifier: GPL-2.0-or-later
#include "projected_cell.h"

#include <catch2/catch.hpp>
#include <memory>
#include <random>

#include "handeye/core/checkerboard.h"
#include "handeye/core/evaluation.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/result_json.h"
#include "support/test_support.h"

namespace handeye::test {

SyntheticScene ProjectedSmallCell(int poses, std::uint64_t pose_seed, bool bumped) {
  SceneOptions options;
  options.cell = "small";
  options.num_cameras = 2;
  options.num_poses = poses;
  options.pose_seed = pose_seed;
  if (bumped) {
    options.bumped_camera = "cam0";
    options.bump_mm = 5.0;
    options.bump_deg = 0.2;
  }
  SyntheticScene scene = MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
  std::mt19937_64 rng(pose_seed + 1);
  AddProjectedObservations(&scene, 0.1, &rng);
  return scene;
}

std::string CalibratedSmallCell(const std::string& dir, int poses) {
  SaveObservations(ProjectedSmallCell(poses).dataset, dir + "/obs.json");
  std::string out;
  REQUIRE(RunHandeye("calibrate " + dir + "/obs.json -o " + dir + "/result.json -q", &out) == 0);
  return out;
}

double MeanCameraErrorMm(const std::string& result_path, const std::string& truth_path) {
  return EvaluateAgainstTruth(LoadResult(result_path), LoadGroundTruth(truth_path))
      .mean_translation_mm;
}

}  // namespace handeye::test
