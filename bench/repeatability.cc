// SPDX-License-Identifier: GPL-2.0-or-later
// Real robots are not exact: with robot pose error of 0.5–1 mm / 0.05–0.1°,
// how close is each method to the truth, and how much does its answer move
// when a quarter of the poses is left out? Rendered and detected images.
//
//   bench_repeatability --cells small,medium,large --poses 8,16,30
//       --robot 0.5/0.05,1/0.1 --seeds 5 --folds 8 --methods joint,park   (one line)
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <set>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/evaluation.h"
#include "handeye/core/transform.h"
#include "handeye/sim/simulation.h"
#include "support/bench_support.h"

using namespace handeye;
using namespace handeye::bench;

namespace {

struct Args {
  std::string cells = "small,medium,large";
  std::string poses = "8,16,30";
  std::string robot = "0.5/0.05,1/0.1";
  int seeds = 5;
  int folds = 8;
  std::string methods = "joint,park";
  std::string source = "images";
  std::string json;
  int threads = 0;
};

struct Stats {
  std::vector<double> e_t_mm, e_r_deg;
  std::vector<double> spread_mm, spread_deg;  ///< per camera: RMS over folds of the move from the full solve
  /// Joint only, per camera: the move an efficient unbiased estimator makes
  /// (below).
  std::vector<double> efficient_mm;
  int failures = 0, fold_failures = 0;
};

/// The dataset without the observations of the given poses.
Dataset Without(const Dataset& dataset, const std::set<std::string>& poses) {
  Dataset out = dataset;
  out.observations.clear();
  for (const Observation& obs : dataset.observations)
    if (!poses.count(obs.pose_id)) out.observations.push_back(obs);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"handeye repeatability under robot pose error: leave 25 % of the poses out"};
  Args args;
  app.add_option("--cells", args.cells, "comma-separated: small, medium, large");
  app.add_option("--poses", args.poses, "comma-separated pose counts");
  app.add_option("--robot", args.robot, "comma-separated robot noise MM/DEG (σ per axis, σ of the angle)");
  app.add_option("--seeds", args.seeds, "scenes per configuration");
  app.add_option("--folds", args.folds, "random leave-25%-out subsets per scene");
  app.add_option("--methods", args.methods, "comma-separated methods");
  app.add_option("--source", args.source, "images (rendered + detected) or projected (true pixels + 0.1 px)");
  app.add_option("--json", args.json, "also write the numbers to this JSON file");
  app.add_option("--threads", args.threads, "render/detect threads (0 = all cores)");
  CLI11_PARSE(app, argc, argv);
  const std::vector<std::string> methods = SplitList(args.methods);

  nlohmann::ordered_json json = nlohmann::ordered_json::array();
  Table table({"cell", "poses", "robot mm/deg", "method", "e_t^GT mm", "e_θ^GT deg", "spread mm",
               "spread deg", "efficient spread mm", "failed"});
  for (const std::string& cell : SplitList(args.cells))
    for (const std::string& poses_text : SplitList(args.poses))
      for (const std::string& robot : SplitList(args.robot)) {
        const int poses = std::stoi(poses_text);
        const double robot_mm = std::stod(robot.substr(0, robot.find('/')));
        const double robot_deg = std::stod(robot.substr(robot.find('/') + 1));
        std::map<std::string, Stats> stats;
        for (int seed = 1; seed <= args.seeds; ++seed) {
          SceneOptions options;
          options.cell = cell;
          options.num_poses = poses;
          options.seed = static_cast<std::uint64_t>(seed);
          options.pose_noise_mm = robot_mm;
          options.pose_noise_deg = robot_deg;
          SyntheticScene scene = MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
          if (args.source == "images") {
            RenderOptions render;
            render.seed = static_cast<std::uint64_t>(seed) * 1000003u;
            render.every_view = false;  // views without the target add nothing to a solve
            DetectSimulated(&scene, render, args.threads);
          } else {
            std::mt19937_64 noise(static_cast<std::uint64_t>(seed) * 7919u);
            AddProjectedObservations(&scene, 0.1, &noise);
          }
          // The same folds for every method: each leaves out a random quarter of the poses.
          std::mt19937_64 rng(static_cast<std::uint64_t>(seed) * 104729u + poses);
          std::vector<std::set<std::string>> folds;
          for (int f = 0; f < args.folds; ++f) {
            std::vector<std::string> ids;
            for (const RobotPose& pose : scene.dataset.poses) ids.push_back(pose.id);
            std::shuffle(ids.begin(), ids.end(), rng);
            folds.emplace_back(ids.begin(), ids.begin() + std::max<size_t>(1, ids.size() / 4));
          }
          // Every method's solves on all poses and on each fold; nullopt where it failed.
          std::map<std::string, std::optional<CalibrationResult>> full;
          std::map<std::string, std::vector<std::optional<CalibrationResult>>> parts;
          for (const std::string& method : methods) {
            CalibrationOptions calibration;
            calibration.method = *ParseMethod(method);
            try {
              full[method] = Calibrate(scene.dataset, calibration);
            } catch (const std::exception&) {
              ++stats[method].failures;
            }
            for (const auto& fold : folds) {
              try {
                parts[method].push_back(Calibrate(Without(scene.dataset, fold), calibration));
              } catch (const std::exception&) {
                parts[method].push_back(std::nullopt);
                ++stats[method].fold_failures;
              }
            }
          }
          // The spread is compared on the same cameras: those every method
          // calibrated, on all poses and in the fold (a camera left with one or
          // two views is calibrated by the joint solve, not by a closed form).
          auto calibrated = [](const std::optional<CalibrationResult>& r, size_t k) {
            return r && r->cameras[k].calibrated;
          };
          std::map<std::string, std::map<size_t, std::vector<double>>> moved_m, moved_rad;
          for (size_t f = 0; f < folds.size(); ++f)
            for (size_t k = 0; k < scene.dataset.cameras.size(); ++k) {
              bool everyone = true;
              for (const std::string& method : methods)
                everyone = everyone && calibrated(full[method], k) && calibrated(parts[method][f], k);
              if (!everyone) continue;
              for (const std::string& method : methods) {
                const CameraResult& a = parts[method][f]->cameras[k];
                const CameraResult& b = full[method]->cameras[k];
                moved_m[method][k].push_back((a.T_cam.translation() - b.T_cam.translation()).norm());
                moved_rad[method][k].push_back(RotationDistance(a.T_cam.rotation(), b.T_cam.rotation()));
              }
            }
          // What an efficient unbiased estimator moves by: with Σ the
          // covariance of its all-poses answer and Σ_f that of a fold's (the
          // same data less a quarter of the poses), the fold's answer minus the
          // full one has covariance Σ_f - Σ, about Σ (N / N_f - 1). Σ is the
          // joint result's, solved with the simulated robot σ given, which on
          // projected cells is honest (median e/σ 0.74-0.81 at 8 poses, 0.89
          // for an exact σ); no estimator without bias moves less.
          if (stats.count("joint") && robot_mm > 0) {
            CalibrationOptions informed;
            informed.robot_sigma_mm = robot_mm;
            informed.robot_sigma_deg =
                robot_deg / std::sqrt(3.0);  // the simulator's turn, per axis
            const double n = static_cast<double>(scene.dataset.poses.size());
            const double n_fold = n - static_cast<double>(std::max<size_t>(1, scene.dataset.poses.size() / 4));
            try {
              const CalibrationResult bound = Calibrate(scene.dataset, informed);
              for (const auto& [k, moves] : moved_m["joint"])
                if (bound.cameras[k].sigma)
                  stats["joint"].efficient_mm.push_back(bound.cameras[k].sigma->position_mm *
                                                        std::sqrt(n / n_fold - 1.0));
            } catch (const std::exception&) {
            }
          }
          for (const std::string& method : methods) {
            Stats& s = stats[method];
            if (full[method]) {
              const Evaluation eval = EvaluateAgainstTruth(*full[method], scene.truth);
              s.e_t_mm.push_back(eval.mean_translation_mm);
              s.e_r_deg.push_back(eval.mean_rotation_deg);
            }
            for (const auto& [k, moves] : moved_m[method]) {
              s.spread_mm.push_back(1000.0 * Rms(moves));
              s.spread_deg.push_back(Rms(moved_rad[method][k]) * 180.0 / M_PI);
            }
          }
          std::fprintf(stderr, "\r%s, %d poses, robot %s: seed %d/%d   ", cell.c_str(), poses, robot.c_str(), seed,
                       args.seeds);
        }
        for (const std::string& method : methods) {
          const Stats& s = stats[method];
          table.Add({cell, poses_text, robot, method, Format("%.3f", Mean(s.e_t_mm)), Format("%.4f", Mean(s.e_r_deg)),
                     Format("%.3f", Mean(s.spread_mm)), Format("%.4f", Mean(s.spread_deg)),
                     s.efficient_mm.empty() ? std::string() : Format("%.3f", Mean(s.efficient_mm)),
                     Format("%d/%d (+%d folds)", s.failures, args.seeds, s.fold_failures)});
          json.push_back({{"cell", cell}, {"poses", poses}, {"robot_mm", robot_mm}, {"robot_deg", robot_deg},
                          {"method", method}, {"e_t_gt_mm", Mean(s.e_t_mm)}, {"e_theta_gt_deg", Mean(s.e_r_deg)},
                          {"spread_mm", Mean(s.spread_mm)}, {"spread_deg", Mean(s.spread_deg)},
                          {"efficient_spread_mm", s.efficient_mm.empty() ? nlohmann::ordered_json()
                                                                         : nlohmann::ordered_json(Mean(s.efficient_mm))},
                          {"failures", s.failures}, {"fold_failures", s.fold_failures}});
        }
      }
  std::fprintf(stderr, "\n");
  std::printf("%d seeds per row, %d folds each leaving out 25 %% of the poses; spread = RMS over folds of the "
              "camera's move from the all-poses solve, mean over cameras and seeds, on the cameras every method "
              "calibrated in the fold; efficient spread = what an unbiased estimator as good as the data allow "
              "moves by (joint's σ with the simulated robot σ given, × sqrt(N / N_fold - 1)); source %s\n\n%s\n",
              args.seeds, args.folds, args.source.c_str(), table.Markdown().c_str());
  if (!args.json.empty()) std::ofstream(args.json) << json.dump(2) << "\n";
  return 0;
}
