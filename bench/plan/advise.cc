// SPDX-License-Identifier: GPL-2.0-or-later
// Does `handeye advise` fix a camera left at 4 views? Per seed: a medium cell
// captured with the simulator's sampler, one camera's views cut to its first
// 4; solve, ask for --added poses, record them (same faults), solve again,
// and compare that camera's reported σ and true position error before and after;
// and, for every camera, the σ advise expected after its proposals against
// the σ the solve then reported. With --intrinsics-off the given intrinsics
// are off (the views are the true cameras').
//
//   bench_plan_advise --seeds 6 --added 4 [--intrinsics-off 0.5/0]
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/evaluation.h"
#include "handeye/core/plan_advice.h"
#include "handeye/sim/synthetic.h"
#include "support/bench_support.h"

using namespace handeye;
using namespace handeye::bench;

namespace {

constexpr char kCamera[] = "cam0";

/// Observes the scene (true pixels + noise) and keeps camera kCamera only at `kept` poses or new ones (index ≥ first_new).
void ObserveCut(SyntheticScene* scene, double noise_px, std::uint64_t seed, std::set<std::string>* kept,
                size_t first_new) {
  std::mt19937_64 rng(seed);
  AddProjectedObservations(scene, noise_px, &rng);
  std::vector<Observation> out;
  for (const Observation& obs : scene->dataset.observations) {
    const bool fresh = static_cast<size_t>(scene->dataset.PoseIndex(obs.pose_id)) >= first_new;
    if (obs.camera == kCamera && !fresh && !kept->count(obs.pose_id)) {
      if (kept->size() >= 4) continue;
      kept->insert(obs.pose_id);
    }
    out.push_back(obs);
  }
  scene->dataset.observations = out;
}

/// kCamera's reported σ and true error (mm).
std::pair<double, double> CameraOutcome(const CalibrationResult& result, const GroundTruth& truth) {
  double sigma = 0, error = 0;
  for (const CameraResult& c : result.cameras)
    if (c.name == kCamera && c.sigma) sigma = c.sigma->position_mm;
  for (const CameraError& e : EvaluateAgainstTruth(result, truth).cameras)
    if (e.name == kCamera) error = e.translation_mm;
  return {sigma, error};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"handeye: advise on a camera left at 4 views"};
  int seeds = 6, first_seed = 3001, poses = 24, added = 4;
  std::string cell = "medium";
  double noise_px = 0.2, robot_mm = 0.3, robot_deg = 0.03;
  app.add_option("--seeds", seeds, "scenes");
  app.add_option("--first-seed", first_seed, "seed of the first scene");
  app.add_option("--cell", cell, "cell");
  app.add_option("--poses", poses, "poses of the first capture");
  app.add_option("--added", added, "poses advise proposes");
  std::string intrinsics_off = "0/0";
  app.add_option(
      "--intrinsics-off", intrinsics_off,
      "PCT/PX: the given intrinsics off by PCT % in focal length and PX in the principal point "
      "(OffsetIntrinsics)");
  CLI11_PARSE(app, argc, argv);
  IntrinsicsOffset offset;
  if (!ParseIntrinsicsOffset(intrinsics_off, &offset)) {
    std::fprintf(stderr, "--intrinsics-off: PCT/PX, e.g. 0.5/3, got '%s'\n",
                 intrinsics_off.c_str());
    return 2;
  }
  const auto target = std::make_shared<const CheckerboardTarget>(7, 4, 0.04);
  Table table({"seed", "sigma before mm", "sigma after mm", "predicted after mm", "error before mm", "error after mm",
               "poses with cam0 added"});
  std::vector<double> sigma_ratio, error_ratio, errors_before, errors_after;
  std::vector<double> forecast_ratio;  // every camera: expected after / reported after
  for (int i = 0; i < seeds; ++i) {
    SceneOptions options;
    options.cell = cell;
    options.num_poses = poses;
    options.seed = first_seed + i;
    options.pose_noise_mm = robot_mm;
    options.pose_noise_deg = robot_deg;
    SyntheticScene first = MakeScene(options, target);
    std::set<std::string> kept;
    ObserveCut(&first, noise_px, options.seed, &kept, first.dataset.poses.size());
    OffsetIntrinsics(offset, &first.dataset);
    try {
      const CalibrationResult before = Calibrate(first.dataset, CalibrationOptions{});
      const PlanCell plan_cell = PlanCellOfResult(first.dataset, before, std::nullopt);
      PlanOptions plan_options;
      plan_options.poses = added;
      plan_options.seed = options.seed;
      const Advice advice = Advise(plan_cell, RecordedPoses(first.dataset, before), plan_options);
      SceneOptions again = options;
      for (const auto& pose : first.truth.poses) again.given_poses.push_back(pose.T_base_ee_true);
      int with_camera = 0;
      for (const PlannedPose& pose : advice.next.poses) {
        again.given_poses.push_back(pose.T_base_ee);
        for (const std::string& name : pose.cameras) with_camera += name == kCamera;
      }
      again.num_poses = static_cast<int>(again.given_poses.size());
      SyntheticScene second = MakeScene(again, target);
      ObserveCut(&second, noise_px, options.seed, &kept, first.dataset.poses.size());
      OffsetIntrinsics(offset, &second.dataset);
      const CalibrationResult after = Calibrate(second.dataset, CalibrationOptions{});
      if (!advice.next.poses.empty())
        for (const CameraResult& c : after.cameras) {
          const auto& expected = advice.next.poses.back().sigma_after;
          if (c.sigma && expected.count(c.name))
            forecast_ratio.push_back(expected.at(c.name).position_mm / c.sigma->position_mm);
        }
      const auto [sigma0, error0] = CameraOutcome(before, first.truth);
      const auto [sigma1, error1] = CameraOutcome(after, second.truth);
      sigma_ratio.push_back(sigma0 / sigma1);
      error_ratio.push_back(error0 / error1);
      errors_before.push_back(error0);
      errors_after.push_back(error1);
      table.Add({std::to_string(options.seed), Format("%.3f", sigma0), Format("%.3f", sigma1),
                 Format("%.3f", advice.next.poses.empty() ? 0.0 : advice.next.poses.back().sigma_after.at(kCamera).position_mm),
                 Format("%.3f", error0), Format("%.3f", error1), Format("%d of %zu", with_camera, advice.next.poses.size())});
    } catch (const std::exception& e) {
      std::fprintf(stderr, "seed %llu: %s\n", (unsigned long long)options.seed, e.what());
    }
  }
  std::printf("%s", table.Markdown().c_str());
  if (!sigma_ratio.empty())
    std::printf("\nmedian improvement of %s: sigma %.2fx, true error %.2fx; RMS true error before / after %.2fx\n",
                kCamera, Median(sigma_ratio), Median(error_ratio), Rms(errors_before) / Rms(errors_after));
  if (!forecast_ratio.empty())
    std::printf("every camera, sigma expected after / reported after: median %s, within 30 %% %s\n",
                RatioRange(forecast_ratio).c_str(), RatiosWithin30Percent(forecast_ratio).c_str());
  return 0;
}
