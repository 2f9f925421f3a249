// SPDX-License-Identifier: GPL-2.0-or-later
// The setup-mistake detective: each usual mistake of a hand-eye dataset is
// tried as a repair of the robot records, and a chain through the repaired
// records scores it (setup_scoring.h). A robot model would otherwise absorb any of them as
// "robot error" and exit 0 with cameras metres off (issue 24).
#include "setup_mistakes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "diagnostics_internal.h"
#include "handeye/core/error.h"
#include "parallel.h"
#include "problem.h"
#include "residuals.h"
#include "robot_error.h"
#include "setup_scoring.h"

namespace handeye::internal {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// A chain that explains the views within this (median view RMS, pixels) is
/// not called mistaken whatever a repair scores: detection noise and the
/// closed form's own error leave about this much on good data. Every usual
/// mistake leaves far more (on rendered cells 37–1000 px; a target 4 % off
/// 1.9 px on METRIC), while on correct rendered records with robot noise of
/// 0.3–1 mm / 0.03–0.1° the repairs score 50× worse than the data as given.
constexpr double kMinMisfitPx = 1.0;
/// Largest and smallest credible robot error (σ per axis): industrial
/// robots repeat to 0.02–0.1 mm and are accurate to a few mm without
/// calibration; 0.5° is far beyond any joint encoder's error.
constexpr double kMaxRobotSigmaMm = 5.0;
constexpr double kMaxRobotSigmaDeg = 0.5;

/// The smallest distance between two of the target's points (its square or
/// tag pitch), metres.
double PointSpacing(const Target& target) {
  const auto& points = target.Points();
  double spacing = std::numeric_limits<double>::infinity();
  for (size_t i = 1; i < points.size(); ++i)
    spacing = std::min(spacing, (points[i].p_target - points[0].p_target).norm());
  return std::isfinite(spacing) ? spacing : 0.0;
}

/// The repair in a few words, for the note that says none was needed.
std::string RepairName(const Hypothesis& h) {
  switch (h.mistake) {
    case Mistake::kInverted:
      return "poses inverted";
    case Mistake::kTransposed:
      return "rotations transposed";
    case Mistake::kXyzwReadAsWxyz:
      return "quaternions read x, y, z, w";
    case Mistake::kWxyzReadAsXyzw:
      return "quaternions read w, x, y, z";
    case Mistake::kTranslationScale:
      return "translations × " + Fixed(h.scale, 3);
    case Mistake::kTargetScale:
      return "target × " + Fixed(1.0 / h.scale, 3);
    case Mistake::kShifted:
      return h.shift > 0 ? "images one pose early" : "images one pose late";
    default:
      return "none";
  }
}

/// What the mistake is and how to fix it, in the user's words.
std::string Diagnosis(const Problem& problem, const Hypothesis& h, const Score& fixed) {
  const Setup setup = problem.dataset->setup;
  const Setup other = setup == Setup::kEyeToHand ? Setup::kEyeInHand : Setup::kEyeToHand;
  std::ostringstream s;
  switch (h.mistake) {
    case Mistake::kInverted: {
      // Both readings fit the same chain; the one that puts what rides on the
      // flange nearer to it is the likelier. Inverted records keep the
      // setup: the holder's content (target for eye_to_hand) rides on the flange.
      const double cameras = Median(fixed.camera_lever_m), target = Median(fixed.target_lever_m);
      const bool inverted_likelier = (setup == Setup::kEyeToHand) == (target < cameras);
      const std::string invert =
          "if your controller reports the base in the flange frame (T_ee_base), invert every pose";
      const std::string swap =
          std::string("if the ") +
          (other == Setup::kEyeInHand
               ? "cameras ride on the robot and the target stands in the cell"
               : "cameras stand in the cell and the target rides on the robot") +
          ", set \"setup\": \"" + SetupName(other) + "\"";
      s << "the robot poses look inverted, or the setup is " << SetupName(other) << " rather than "
        << SetupName(setup) << " (both fit the same chain): with T_base_ee = inverse(given)";
      return s.str() + "|" +
             (inverted_likelier ? invert + "; or, " + swap : swap + "; or, " + invert);
    }
    case Mistake::kTransposed:
      return "the robot rotations look transposed: with each pose's rotation transposed and its "
             "translation "
             "kept|the rotation matrices were likely written column by column, or as R_ee_base "
             "beside t_base_ee; "
             "transpose the 3×3 rotation of every pose";
    case Mistake::kXyzwReadAsWxyz:
      return "the robot quaternions look written x, y, z, w but read as w, x, y, z: with the four "
             "numbers "
             "taken in that order|label them quaternion_xyzw (or write them w first as "
             "quaternion_wxyz)";
    case Mistake::kWxyzReadAsXyzw:
      return "the robot quaternions look written w, x, y, z but read as x, y, z, w: with the four "
             "numbers "
             "taken in that order|label them quaternion_wxyz (or write them w last as "
             "quaternion_xyzw)";
    case Mistake::kTranslationScale:
      if (h.scale > 1.0)
        return "the robot translations look 1000× too small: with every translation × 1000|metres "
               "were "
               "likely written where millimetres are declared (translation_mm); give them as "
               "translation_m";
      return "the robot translations look 1000× too large: with every translation ÷ "
             "1000|millimetres were "
             "likely written where metres are expected (translation_m, or the 4×4 T_base_ee, which "
             "is in "
             "metres); give them as translation_mm or divide by 1000";
    case Mistake::kTargetScale: {
      const double declared = PointSpacing(*problem.dataset->target);
      s << "the target looks " << Fixed(1.0 / h.scale, 3)
        << "× the size declared (the cameras see it move " << Fixed(h.scale, 3)
        << "× as far as the robot moves it): with the target that size|measure the printed "
        << "target and correct its sizes in the dataset (square_size_m and marker_size_m, or "
           "tag_size_m): "
        << "its points' spacing, declared " << Fixed(declared * 1000.0, 1) << " mm, looks "
        << Fixed(declared * 1000.0 / h.scale, 1) << " mm";
      return s.str();
    }
    case Mistake::kShifted:
      s << "the images look shifted against the robot poses by one: each view fits the pose listed "
        << (h.shift > 0 ? "after" : "before") << " its own|pair each image with the "
        << (h.shift > 0 ? "next" : "previous")
        << " robot pose (a pose recorded before its image was taken, or one record or image "
           "missing)";
      return s.str();
    default:
      return "";
  }
}

}  // namespace

SetupVerdict JudgeSetup(const Problem& problem, int threads) {
  SetupVerdict verdict;
  const Problem scoring = ScoringProblem(problem);
  // The data as given first, then every repair: closed forms of every camera
  // for each, on `threads` threads (they were half of a METRIC solve).
  std::vector<Hypothesis> hypotheses = {Hypothesis{}};
  for (const Hypothesis& h : Hypotheses(scoring)) hypotheses.push_back(h);
  std::vector<Score> scores(hypotheses.size());
  ParallelFor(hypotheses.size(), threads,
              [&](std::size_t i) { scores[i] = ScoreOf(scoring, hypotheses[i]); });
  for (size_t i = 0; i < hypotheses.size(); ++i)
    if (hypotheses[i].mistake == Mistake::kTargetScale)
      FitTargetScale(scoring, threads, &hypotheses[i], &scores[i]);
  const Score& given = scores[0];
  verdict.given_px = given.median_rms_px;
  if (given.cameras == 0) return verdict;
  std::optional<Hypothesis> best;
  Score best_score;
  for (std::size_t i = 1; i < hypotheses.size(); ++i) {
    const Hypothesis& h = hypotheses[i];
    const Score& score = scores[i];
    // A repair that leaves cameras unsolved is not compared on fewer views.
    if (score.cameras < given.cameras || !(score.median_rms_px < best_score.median_rms_px))
      continue;
    best = h;
    best_score = score;
  }
  if (!best) return verdict;
  verdict.best_px = best_score.median_rms_px;
  verdict.best = RepairName(*best);
  if (!(given.median_rms_px > kMinMisfitPx)) return verdict;
  // A closed form leaves pixels of its own error where the lens model does
  // not fit the images (the industrial_calibration ChArUco set, a camera
  // without its distortion: 7.5 px as given, its target declared 10 % large
  // 19.0 px, and 5.8 px repaired): a repair the closed forms clearly favour
  // is scored again through refined chains, by what they add to the views'
  // own PnP fits (which no chain goes below, and which such a lens raises).
  std::string refined;
  if (given.median_rms_px < kMistakeRatio * best_score.median_rms_px) {
    if (given.median_rms_px < kRefineRatio * best_score.median_rms_px) return verdict;
    const Score refined_given = ScoreOf(scoring, Hypothesis{}, true);
    Score refined_best = ScoreOf(scoring, *best, true);
    if (best->mistake == Mistake::kTargetScale) RefineTargetScale(scoring, threads, &*best, &refined_best);
    if (refined_best.cameras < refined_given.cameras || !(refined_given.median_rms_px > kMinMisfitPx) ||
        refined_given.median_excess_px < kRefinedMistakeRatio * refined_best.median_excess_px)
      return verdict;
    refined = "; through refined chains from " + Fixed(refined_given.median_rms_px, 1) + " px to " +
              Fixed(refined_best.median_rms_px, 2) + " px, and what they add to each view's own fit from " +
              Fixed(refined_given.median_excess_px, 1) + " px to " +
              Fixed(refined_best.median_excess_px, 2) + " px";
  }
  const std::string diagnosis = Diagnosis(problem, *best, best_score);
  const size_t bar = diagnosis.find('|');
  std::ostringstream message;
  // A chain that puts points behind the cameras scores 1e6 px (ViewErrors).
  const std::string given_px =
      given.median_rms_px < 1e4 ? Fixed(given.median_rms_px, 1) : "over 10000";
  message << diagnosis.substr(0, bar)
          << ", the views' residual through a closed-form chain drops from " << given_px
          << " px to " << Fixed(best_score.median_rms_px, 2) << " px (median over "
          << best_score.views << " views" << refined << "); " << diagnosis.substr(bar + 1)
          << ". To calibrate the data as they are, pass --accept-setup";
  verdict.mistake = message.str();
  return verdict;
}

std::string CheckSetupMistakes(const Problem& problem, int threads) {
  // No time in the note: a result's text is the same however long a run took.
  const SetupVerdict verdict = JudgeSetup(problem, threads);
  if (!verdict.mistake.empty()) throw SolveError(verdict.mistake);
  if (!std::isfinite(verdict.given_px))
    return "the setup checks did not run: no camera has " + std::to_string(kMinScoredViews) +
           " views away from the first and last pose";
  std::string note =
      "the setup checks found no usual mistake: the data as given explain the views with " +
      Fixed(verdict.given_px, 2) + " px through a closed-form chain";
  if (std::isfinite(verdict.best_px))
    note += ", the best repair (" + verdict.best + ") with " + Fixed(verdict.best_px, 2) + " px";
  return note;
}

bool RobotSigmaPlausible(double sigma_m, double sigma_rad) {
  return sigma_m * 1000.0 <= kMaxRobotSigmaMm && sigma_rad / kDeg <= kMaxRobotSigmaDeg;
}

bool RobotPlausible(const RobotPrior& robot) {
  return RobotSigmaPlausible(robot.SettledSigmaM(), robot.SettledSigmaRad());
}

void CheckRobotSigma(const RobotPrior& robot) {
  if (RobotPlausible(robot)) return;
  const double mm = robot.SettledSigmaM() * 1000.0, deg = robot.SettledSigmaRad() / kDeg;
  throw SolveError(
      "the robot's own pose error would have to be σ " + Fixed(mm, 2) + " mm and " + Fixed(deg, 3) +
      " deg per axis to explain the views: more than any industrial robot (" +
      Fixed(kMaxRobotSigmaMm, 0) + " mm, " + Fixed(kMaxRobotSigmaDeg, 1) +
      " deg). A misfit that large is a setup mistake or intrinsics that do not fit "
      "the images: robot poses in another frame, order or unit than declared, images "
      "that do not belong to their poses, the wrong target size, or a lens model the "
      "images do not follow (none of the usual setup mistakes explains it on its own). "
      "Check the dataset; to see whether the intrinsics explain it, rerun with "
      "--refine-intrinsics focal,principal_point (or all); to solve with the robot "
      "taken as exact, --robot-sigma-mm 0 --robot-sigma-deg 0; to calibrate the data "
      "as they are, --accept-setup");
}

}  // namespace handeye::internal
