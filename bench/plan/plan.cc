// SPDX-License-Identifier: GPL-2.0-or-later
// Does a planned capture beat the simulator's own? Per cell and seed: the
// simulator's sampler records --sampler-poses poses; `handeye plan` chooses
// --planned-poses from what a user would know (camera and target poses off
// by a tape measure's 20 mm / 1°); both are observed with the same faults
// (robot pose error, detection noise, lens distortion) and solved with the
// default options. Reports the mean and the worst camera's true position
// error of both, the σ the plan predicted against the σ the solve of the
// planned capture reports, and the RMS of the true errors over the RMS of
// the predicted σ (1 for an honest σ: σ is the RMS of the 3-D position error).
//
//   bench_plan --cells small,medium,large --cameras 4,5,6 --seeds 6
//   bench_plan --source images ...   (rendered and detected instead of projected)
#include "handeye/core/plan.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/evaluation.h"
#include "handeye/sim/plan_cell.h"
#include "handeye/sim/render.h"
#include "handeye/sim/simulation.h"
#include "handeye/sim/synthetic.h"
#include "support/bench_support.h"

using namespace handeye;
using namespace handeye::bench;

namespace {

struct Settings {
  std::string source = "projected";
  double noise_px = 0.2;           // projected: detection noise σ per axis
  double robot_mm = 0.3, robot_deg = 0.03;
  int sampler_poses = 30, planned_poses = 12, candidates = 8000;
  bool given_robot_sigma = false;  // solve with the true robot σ instead of estimating it
  double rough_mm = 20, rough_deg = 1;  // the cell's rough poses: ± of cameras and target
  double uncertainty_margin = PlanOptions{}.uncertainty_margin;
  IntrinsicsOffset intrinsics_off;  // the given intrinsics off (OffsetIntrinsics)
  // Plan for and solve with --refine-intrinsics focal,principal_point; and
  // also solve the planned capture with the true intrinsics and with none.
  bool refine_intrinsics = false;
  bool no_intrinsics = false;  // the dataset gives no intrinsics (set per solve and plan)
  // The solves' camera-to-camera terms (CalibrationOptions::cross_terms),
  // and so the plan's forecast (PlanCell::cross_terms).
  bool cross_terms = true;
  // Further draws of the planned capture's robot error and detection noise
  // (same poses): how far the σ the solve reports scatters on its own, and
  // so how close any forecast of one σ per camera can come to it.
  int noise_draws = 0;
};

/// One capture's outcome against the truth.
struct Outcome {
  bool solved = false;
  std::string why;
  double mean_mm = 0, worst_mm = 0;
  double robot_sigma_mm = 0, robot_sigma_deg = 0;  // as the solve modelled it (0: exact)
  std::string model;                               // the held-out choice's pick, if any
  std::map<std::string, double> error_mm, sigma_mm, own_sigma_mm;
};

void Observe(SyntheticScene* scene, const Settings& settings, std::uint64_t seed) {
  if (settings.source == "images") {
    RenderOptions render;
    render.seed = seed;
    DetectSimulated(scene, render);
    return;
  }
  std::mt19937_64 rng(seed);
  AddProjectedObservations(scene, settings.noise_px, &rng);
}

Outcome Solve(const SyntheticScene& scene, const Settings& settings) {
  Outcome out;
  try {
    CalibrationOptions options;
    if (settings.refine_intrinsics) options.refine_intrinsics = kFocal | kPrincipalPoint;
    options.cross_terms = settings.cross_terms;
    if (settings.given_robot_sigma) {
      options.robot_sigma_mm = settings.robot_mm;
      options.robot_sigma_deg = settings.robot_deg / std::sqrt(3.0);
    }
    // The given intrinsics off as a user's earlier calibration may be: the
    // observations are the true cameras', the solve gets these.
    Dataset dataset = scene.dataset;
    OffsetIntrinsics(settings.intrinsics_off, &dataset);
    if (settings.no_intrinsics)
      for (Camera& camera : dataset.cameras) camera.has_intrinsics = false;
    const CalibrationResult result = Calibrate(dataset, options);
    const Evaluation evaluation = EvaluateAgainstTruth(result, scene.truth);
    for (const CameraError& e : evaluation.cameras) {
      out.error_mm[e.name] = e.translation_mm;
      out.worst_mm = std::max(out.worst_mm, e.translation_mm);
    }
    for (const CameraResult& c : result.cameras)
      if (c.sigma) {
        out.sigma_mm[c.name] = c.sigma->position_mm;
        out.own_sigma_mm[c.name] = c.sigma->OwnPositionMm();
      }
    out.mean_mm = evaluation.mean_translation_mm;
    out.robot_sigma_mm = result.solver.robot_sigma_mm;
    out.robot_sigma_deg = result.solver.robot_sigma_deg;
    if (result.solver.model) out.model = result.solver.model->chosen;
    out.solved = evaluation.cameras.size() == scene.dataset.cameras.size();
    if (!out.solved) out.why = "not every camera calibrated";
  } catch (const std::exception& e) {
    out.why = e.what();
  }
  return out;
}

/// The sampler's and the planned capture solved with the true intrinsics
/// ("true"), the given ones off and refined ("refined", what `settings`
/// asks), off and held ("held") and none given ("none", the planned one
/// from `planned_unknown`, its plan made for intrinsics unknown, which is also
/// solved with the true intrinsics: "planned/true, capture for none"): mean
/// errors into `variants`, and RMS reported σ under NAME/sigma.
void SolveVariants(const SyntheticScene& sampler, const SyntheticScene& planned,
                   const SyntheticScene& planned_unknown, const Settings& settings,
                   std::map<std::string, std::vector<double>>* variants) {
  Settings exact = settings, held = settings, none = settings;
  exact.intrinsics_off = {};
  exact.refine_intrinsics = false;
  held.refine_intrinsics = false;
  none.no_intrinsics = true;
  using Variant = std::pair<const char*, const Settings*>;
  for (const auto& [capture, scene] : {std::make_pair("sampler", &sampler), std::make_pair("planned", &planned)})
    for (const auto& [name, variant] : {Variant("true", &exact), Variant("refined", &settings),
                                        Variant("held", &held), Variant("none", &none)}) {
      const Outcome o =
          Solve(variant == &none && scene == &planned ? planned_unknown : *scene, *variant);
      if (!o.solved) std::fprintf(stderr, "  %s/%s: %s\n", capture, name, o.why.c_str());
      if (o.solved) {
        (*variants)[std::string(capture) + "/" + name].push_back(o.mean_mm);
        // What the solve says the data tell: the true intrinsics' solve by its
        // views alone (its σ less what the given intrinsics' prior adds), the
        // others whole. RMS over the cameras.
        std::vector<double> sigma;
        for (const auto& [camera, value] :
             std::string(name) == "true" ? o.own_sigma_mm : o.sigma_mm)
          sigma.push_back(value);
        if (!sigma.empty())
          (*variants)[std::string(capture) + "/" + name + "/sigma"].push_back(Rms(sigma));
      }
      (*variants)[std::string(capture) + "/" + name + "/tried"].push_back(o.solved ? 1 : 0);
    }
  if (const Outcome o = Solve(planned_unknown, exact); o.solved)
    (*variants)["planned/true, capture for none"].push_back(o.mean_mm);
}

SceneOptions Options(const std::string& cell, int cameras, int poses, std::uint64_t seed, const Settings& s) {
  SceneOptions options;
  options.cell = cell;
  options.num_cameras = cameras;
  options.num_poses = poses;
  options.seed = seed;
  options.pose_noise_mm = s.robot_mm;
  options.pose_noise_deg = s.robot_deg;
  return options;
}

/// The scene options of a planned capture: the cell's, with the plan's poses.
SceneOptions OptionsOfPlan(const std::string& cell, int cameras, std::uint64_t seed,
                           const Settings& s, const CapturePlan& plan) {
  SceneOptions options = Options(cell, cameras, s.planned_poses, seed, s);
  for (const PlannedPose& pose : plan.poses) options.given_poses.push_back(pose.T_base_ee);
  options.num_poses = static_cast<int>(options.given_poses.size());
  return options;
}

/// The plan of `planned_poses` for the sampler's cell as a user would know it;
/// prints the worst σ it predicts for its own capture and for the sampler's.
CapturePlan PlanFor(const SyntheticScene& sampler, std::uint64_t seed, const Settings& s) {
  RoughKnowledge rough;
  rough.seed = seed;
  rough.robot_sigma_mm = s.robot_mm;
  // The simulator turns each record by N(0, σ) about a random axis: σ/√3 per axis.
  rough.robot_sigma_deg = s.robot_deg / std::sqrt(3.0);
  rough.pixel_sigma_px = s.noise_px;
  rough.position_mm = s.rough_mm;
  rough.rotation_deg = s.rough_deg;
  PlanCell cell = PlanCellOfScene(sampler, rough);
  for (PlanCamera& camera : cell.cameras) {
    camera.refine_intrinsics = s.refine_intrinsics || s.no_intrinsics;
    camera.intrinsics_unknown = s.no_intrinsics;
  }
  cell.cross_terms = s.cross_terms;  // the σ forecast for the solve as run
  PlanOptions plan_options;
  plan_options.uncertainty_margin = s.uncertainty_margin;
  plan_options.poses = s.planned_poses;
  plan_options.seed = seed;
  plan_options.candidates = s.candidates;
  const CapturePlan plan = PlanCapture(cell, plan_options);
  if (!plan.failure.empty()) return plan;
  std::vector<Eigen::Isometry3d> sampler_poses;
  for (const auto& pose : sampler.truth.poses) sampler_poses.push_back(pose.T_base_ee_true);
  double sampler_worst_sigma = 0, planned_worst_sigma = 0;
  for (const auto& [name, sigma] : PredictSigma(cell, sampler_poses))
    sampler_worst_sigma = std::max(sampler_worst_sigma, sigma.position_mm);
  for (const auto& [name, sigma] : plan.poses.back().sigma_after)
    planned_worst_sigma = std::max(planned_worst_sigma, sigma.position_mm);
  std::fprintf(stderr, "predicted worst sigma: sampler %.3f planned %.3f\n", sampler_worst_sigma, planned_worst_sigma);
  return plan;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"handeye: a planned capture against the simulator's own"};
  std::string cells = "small,medium,large", cameras_list = "4,5,6";
  int seeds = 6, first_seed = 2001;
  Settings s;
  app.add_option("--cells", cells, "cells");
  app.add_option("--cameras", cameras_list, "cameras per cell, one per cell or one for all");
  app.add_option("--seeds", seeds, "scenes per cell");
  app.add_option("--first-seed", first_seed, "seed of the first scene");
  app.add_option("--source", s.source, "projected (true pixels + noise) or images (rendered and detected)")
      ->check(CLI::IsMember({"projected", "images"}));
  app.add_option("--noise", s.noise_px, "projected: detection noise σ per axis (px)");
  app.add_option("--robot-mm", s.robot_mm, "robot translation error σ per axis (mm)");
  app.add_option("--robot-deg", s.robot_deg, "robot rotation error σ (deg)");
  app.add_option("--sampler-poses", s.sampler_poses, "poses of the simulator's own capture");
  app.add_option("--planned-poses", s.planned_poses, "poses of the planned capture");
  app.add_option("--candidates", s.candidates, "candidate poses the planner draws in the region");
  app.add_option("--rough-mm", s.rough_mm, "the cell's rough poses: ± of each camera's and the target's position (mm)");
  app.add_option("--rough-deg", s.rough_deg, "the cell's rough poses: ± of their orientation (deg)");
  app.add_option("--uncertainty-margin", s.uncertainty_margin,
                 "PlanOptions::uncertainty_margin: share of the rough ± kept free around the target (0-1)");
  app.add_flag("--given-robot-sigma", s.given_robot_sigma,
               "solve with the true robot error as the prior (default: the solve estimates it)");
  app.add_flag("--refine-intrinsics", s.refine_intrinsics,
               "plan for and solve with --refine-intrinsics focal,principal_point, and table each capture "
               "solved with the true intrinsics, the given ones (--intrinsics-off) refined or held, and none");
  bool no_cross_terms = false;
  app.add_flag(
      "--no-cross-terms", no_cross_terms,
      "solve without the camera-to-camera terms, as the planner predicts (they reuse the points of "
      "each view that other cameras share, which the σ the solve reports counts as new data)");
  std::string intrinsics_off = "0/0";
  app.add_option("--intrinsics-off", intrinsics_off,
                 "PCT/PX: the given intrinsics off by PCT % in focal length and PX in the principal point "
                 "(OffsetIntrinsics: even cameras f +, cx +, cy -; odd the other way); the observations are "
                 "the true cameras'");
  app.add_option(
      "--noise-draws", s.noise_draws,
      "further draws of each planned capture's robot error and detection noise (same poses): "
      "tables the plan's forecast against every draw's reported σ, and against the best "
      "forecast of one σ per camera (the median of the draws)");
  CLI11_PARSE(app, argc, argv);
  s.cross_terms = !no_cross_terms;
  if (!ParseIntrinsicsOffset(intrinsics_off, &s.intrinsics_off)) {
    std::fprintf(stderr, "--intrinsics-off: PCT/PX, e.g. 1/3, got '%s'\n", intrinsics_off.c_str());
    return 2;
  }

  const auto target = std::make_shared<const CheckerboardTarget>(7, 4, 0.04);
  const std::vector<std::string> cell_names = SplitList(cells), camera_counts = SplitList(cameras_list);
  Table table({"cell", "cameras", "seeds solved", "mean err sampler mm", "mean err planned mm",
               "worst err sampler mm", "worst err planned mm", "worst improvement",
               "predicted/reported sigma (median, min, max)", "cameras predicted within 30 %",
               "RMS true err / RMS predicted sigma", "RMS true err / RMS reported sigma",
               "plans failed", "planned views seen whole / claimed"});
  // With --refine-intrinsics: each capture solved with the true intrinsics,
  // with the given ones (off by --intrinsics-off) refined, and with none.
  Table draws({"cell", "cameras", "draws per capture", "forecast within 30 % of the reported σ",
               "median of the draws within 30 % of the reported σ"});
  Table refinement({"cell", "cameras", "capture", "seeds solved", "true intrinsics mm",
                    "off, refined mm", "refined / true", "reported σ refined / true (own)",
                    "forecast σ refined / exact", "off, held mm", "no intrinsics mm", "none / true",
                    "none / true, one capture", "reported σ none / true (own)",
                    "forecast σ none / exact"});
  for (size_t c = 0; c < cell_names.size(); ++c) {
    const int cameras = std::stoi(camera_counts[std::min(c, camera_counts.size() - 1)]);
    std::map<std::string, std::vector<double>> variants;  // capture/variant -> mean error per seed
    std::vector<double> mean_sampler, mean_planned, worst_sampler, worst_planned, ratios;
    std::vector<double> predicted_sigma, reported_sigma, planned_errors;  // per camera of the planned captures
    // --noise-draws: predicted over reported σ per camera and draw, and the
    // median of the camera's draws over each.
    std::vector<double> draw_ratios, oracle_ratios;
    // Each planned camera's forecast σ, and the same views' were its
    // intrinsics exact (CapturePlan::intrinsics_exact_mm).
    std::vector<double> forecast_sigma, forecast_exact_intrinsics;
    // The same for the capture planned for intrinsics unknown.
    std::vector<double> forecast_unknown;
    int solved = 0, failed_plans = 0, claimed_views = 0, whole_views = 0;
    for (int i = 0; i < seeds; ++i) {
      const std::uint64_t seed = first_seed + i;
      SyntheticScene sampler = MakeScene(Options(cell_names[c], cameras, s.sampler_poses, seed, s), target);
      const CapturePlan plan = PlanFor(sampler, seed, s);
      if (!plan.failure.empty()) {
        ++failed_plans;
        std::fprintf(stderr, "%s seed %llu: plan failed: %s\n", cell_names[c].c_str(), (unsigned long long)seed,
                     plan.failure.c_str());
        continue;
      }
      const SceneOptions planned_options = OptionsOfPlan(cell_names[c], cameras, seed, s, plan);
      SyntheticScene planned = MakeScene(planned_options, target);
      Observe(&sampler, s, seed);
      Observe(&planned, s, seed + 7919);
      // The views the plan counts on, against those the true cell gives with the whole target.
      for (const PlannedPose& pose : plan.poses) claimed_views += static_cast<int>(pose.cameras.size());
      for (const Observation& obs : planned.dataset.observations)
        whole_views += obs.ids.size() == target->Points().size() ? 1 : 0;
      const Outcome a = Solve(sampler, s), b = Solve(planned, s);
      if (!a.solved || !b.solved) {
        std::fprintf(stderr, "%s seed %llu: %s %s\n", cell_names[c].c_str(), (unsigned long long)seed,
                     a.why.c_str(), b.why.c_str());
        continue;
      }
      ++solved;
      if (s.refine_intrinsics) {
        // The capture planned for intrinsics unknown, for the solve given none.
        Settings unknown = s;
        unknown.no_intrinsics = true;
        const CapturePlan plan_unknown = PlanFor(sampler, seed, unknown);
        // Where that plan fails, the none solve takes the capture planned above.
        std::optional<SyntheticScene> planned_unknown;
        if (plan_unknown.failure.empty()) {
          planned_unknown =
              MakeScene(OptionsOfPlan(cell_names[c], cameras, seed, s, plan_unknown), target);
          Observe(&*planned_unknown, s, seed + 7919);
          for (const auto& [name, predicted] : plan_unknown.poses.back().sigma_after)
            forecast_unknown.push_back(predicted.position_mm);
        }
        SolveVariants(sampler, planned, planned_unknown ? *planned_unknown : planned, s, &variants);
      }
      for (const auto& [name, predicted] : plan.poses.back().sigma_after) {
        forecast_sigma.push_back(predicted.position_mm);
        forecast_exact_intrinsics.push_back(plan.intrinsics_exact_mm.at(name));
      }
      mean_sampler.push_back(a.mean_mm);
      mean_planned.push_back(b.mean_mm);
      worst_sampler.push_back(a.worst_mm);
      worst_planned.push_back(b.worst_mm);
      for (const auto& [name, predicted] : plan.poses.back().sigma_after)
        if (b.sigma_mm.count(name)) {
          ratios.push_back(predicted.position_mm / b.sigma_mm.at(name));
          predicted_sigma.push_back(predicted.position_mm);
          reported_sigma.push_back(b.sigma_mm.at(name));
          planned_errors.push_back(b.error_mm.at(name));
          std::fprintf(stderr,
                       "  %s predicted %.3f (own %.3f) reported %.3f (own %.3f) true error %.3f\n",
                       name.c_str(), predicted.position_mm, predicted.own_position_mm,
                       b.sigma_mm.at(name), b.own_sigma_mm.at(name), b.error_mm.at(name));
        }
      if (s.noise_draws > 0) {
        // The planned capture drawn again: each camera's reported σ over the
        // draws, the main one first.
        std::map<std::string, std::vector<double>> drawn;
        for (const auto& [name, sigma] : b.sigma_mm) drawn[name].push_back(sigma);
        for (int d = 1; d <= s.noise_draws; ++d) {
          SceneOptions again = planned_options;
          again.pose_seed = seed * 1000 + d;
          SyntheticScene redrawn = MakeScene(again, target);
          Observe(&redrawn, s, seed * 1000 + 7919 + d);
          const Outcome o = Solve(redrawn, s);
          for (const auto& [name, sigma] : o.sigma_mm) drawn[name].push_back(sigma);
        }
        for (const auto& [name, predicted] : plan.poses.back().sigma_after) {
          const auto it = drawn.find(name);
          if (it == drawn.end()) continue;
          const double median = Median(it->second);
          for (double reported : it->second) {
            draw_ratios.push_back(predicted.position_mm / reported);
            oracle_ratios.push_back(median / reported);
          }
          std::fprintf(stderr,
                       "  %s predicted %.3f, reported over %zu draws: median %.3f (%.3f-%.3f)\n",
                       name.c_str(), predicted.position_mm, it->second.size(), median,
                       *std::min_element(it->second.begin(), it->second.end()),
                       *std::max_element(it->second.begin(), it->second.end()));
        }
      }
      std::fprintf(stderr,
                   "%s seed %llu: sampler mean %.3f worst %.3f | planned mean %.3f worst %.3f, "
                   "robot %.3f mm / "
                   "%.4f deg (%s); sampler's robot %.3f mm / %.4f deg (%s)\n",
                   cell_names[c].c_str(), (unsigned long long)seed, a.mean_mm, a.worst_mm,
                   b.mean_mm, b.worst_mm, b.robot_sigma_mm, b.robot_sigma_deg,
                   b.model.empty() ? "no choice" : b.model.c_str(), a.robot_sigma_mm,
                   a.robot_sigma_deg, a.model.empty() ? "no choice" : a.model.c_str());
    }
    if (solved == 0) {
      std::printf("%s, %d cameras: %d of %d plans failed, none solved\n", cell_names[c].c_str(), cameras,
                  failed_plans, seeds);
      continue;
    }
    for (const std::string capture : {"sampler", "planned"}) {
      if (!s.refine_intrinsics) break;
      const auto& v = variants;
      // Mean over the seeds that solved; "failed" where none did.
      auto mean = [&](const std::string& name) {
        const auto it = v.find(capture + "/" + name);
        return it == v.end() || it->second.empty() ? NAN : Mean(it->second);
      };
      auto solved_of = [&](const std::string& name) {
        const std::vector<double>& tried = v.at(capture + "/" + name + "/tried");
        return Format("%d/%d", static_cast<int>(std::count(tried.begin(), tried.end(), 1.0)),
                      static_cast<int>(tried.size()));
      };
      auto mm = [&](const std::string& name) {
        return std::isnan(mean(name)) ? std::string("failed") : Format("%.3f", mean(name));
      };
      auto ratio = [&](const std::string& name) {
        return std::isnan(mean(name)) ? std::string("-") : Format("%.2fx", mean(name) / mean("true"));
      };
      // The same ratio in the σ the solves report: what the capture's data
      // allow, where the error ratio is what the estimator reached.
      auto rms_sigma = [&](const std::string& name) {
        const auto it = v.find(capture + "/" + name + "/sigma");
        return it == v.end() || it->second.empty() ? NAN : Rms(it->second);
      };
      auto sigma_ratio = [&](const std::string& name) {
        const double r = rms_sigma(name) / rms_sigma("true");
        return std::isnan(r) ? std::string("-") : Format("%.2fx", r);
      };
      refinement.Add(
          {cell_names[c], std::to_string(cameras),
           capture == "sampler" ? Format("sampler, %d poses", s.sampler_poses)
                                : Format("planned, %d poses", s.planned_poses),
           solved_of("true"), mm("true"), mm("refined"), ratio("refined"), sigma_ratio("refined"),
           capture == "sampler"
               ? std::string("-")
               : Format("%.2fx", Rms(forecast_sigma) / Rms(forecast_exact_intrinsics)),
           mm("held"), mm("none") + " (" + solved_of("none") + " solved)", ratio("none"),
           std::isnan(mean("true, capture for none"))
               ? std::string("-")
               : Format("%.2fx", mean("none") / mean("true, capture for none")),
           sigma_ratio("none"),
           capture == "sampler" || forecast_unknown.empty()
               ? std::string("-")
               : Format("%.2fx", Rms(forecast_unknown) / Rms(forecast_exact_intrinsics))});
    }
    if (s.noise_draws > 0)
      draws.Add({cell_names[c], std::to_string(cameras), std::to_string(s.noise_draws + 1),
                 RatiosWithin30Percent(draw_ratios), RatiosWithin30Percent(oracle_ratios)});
    table.Add({cell_names[c], std::to_string(cameras), Format("%d/%d", solved, seeds),
               Format("%.3f", Mean(mean_sampler)), Format("%.3f", Mean(mean_planned)),
               Format("%.3f", Mean(worst_sampler)), Format("%.3f", Mean(worst_planned)),
               Format("%.2fx", Mean(worst_sampler) / Mean(worst_planned)), RatioRange(ratios),
               RatiosWithin30Percent(ratios),
               Format("%.2f", Rms(planned_errors) / Rms(predicted_sigma)),
               Format("%.2f", Rms(planned_errors) / Rms(reported_sigma)),
               std::to_string(failed_plans), Format("%d/%d", whole_views, claimed_views)});
  }
  std::printf("%s", table.Markdown().c_str());
  if (s.noise_draws > 0) std::printf("\n%s", draws.Markdown().c_str());
  if (s.refine_intrinsics) std::printf("\n%s", refinement.Markdown().c_str());
  return 0;
}
