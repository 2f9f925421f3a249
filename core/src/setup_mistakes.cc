// SPDX-License-Identifier: GPL-2.0-or-later
// The setup-mistake detective: each usual mistake of a hand-eye dataset is
// tried as a repair of the robot records, and a closed form on the repaired
// records scores it. A robot model would otherwise absorb any of them as
// "robot error" and exit 0 with cameras metres off (issue 24).
#include "setup_mistakes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "closed_form.h"
#include "diagnostics_internal.h"
#include "handeye/core/error.h"
#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"
#include "parallel.h"
#include "problem.h"
#include "refinement.h"
#include "residuals.h"
#include "robot_error.h"

namespace handeye::internal {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// A camera is scored only with this many views: fewer leave a closed form
/// free to fit a wrong record set too.
constexpr size_t kMinScoredViews = 6;
/// Views scored per camera (spread over its views): enough for a median,
/// few enough to keep METRIC's 4 × 250 views well under a second.
constexpr size_t kScoredViews = 40;
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

enum class Mistake {
  kAsGiven,
  kInverted,          ///< T_ee_base given as T_base_ee (or the other setup)
  kTransposed,        ///< R_base_ee transposed, translation kept
  kXyzwReadAsWxyz,    ///< a quaternion x, y, z, w read as w, x, y, z
  kWxyzReadAsXyzw,    ///< and the reverse
  kTranslationScale,  ///< the robot's translations in another unit (× 1000, ÷ 1000)
  kTargetScale,       ///< the target's size off: camera motions scaled against the robot's
  kShifted,           ///< each image belongs to the next (or previous) pose record
};

struct Hypothesis {
  Mistake mistake = Mistake::kAsGiven;
  double scale = 1.0;  ///< kTranslationScale, kTargetScale: the records' translations × this
  int shift = 0;       ///< kShifted: the view of pose j takes the record of pose j + shift
};

/// A robot record as it would be were the hypothesis' mistake made.
Eigen::Isometry3d Repaired(const Eigen::Isometry3d& T_base_ee, const Hypothesis& h) {
  Eigen::Isometry3d T = T_base_ee;
  switch (h.mistake) {
    case Mistake::kInverted:
      return T_base_ee.inverse();
    case Mistake::kTransposed:
      T.linear() = T_base_ee.linear().transpose();
      return T;
    case Mistake::kXyzwReadAsWxyz:
    case Mistake::kWxyzReadAsXyzw: {
      // The loaded rotation's quaternion holds the file's four numbers in
      // the order they were read; put them back in the order they were written.
      const Eigen::Quaterniond q(T_base_ee.linear());
      const Eigen::Quaterniond written = h.mistake == Mistake::kXyzwReadAsWxyz
                                             ? Eigen::Quaterniond(q.z(), q.w(), q.x(), q.y())
                                             : Eigen::Quaterniond(q.x(), q.y(), q.z(), q.w());
      T.linear() = written.normalized().toRotationMatrix();
      return T;
    }
    case Mistake::kTranslationScale:
    case Mistake::kTargetScale:
      T.translation() *= h.scale;
      return T;
    default:
      return T;
  }
}

/// How well a hypothesis explains the views.
struct Score {
  double median_rms_px = std::numeric_limits<double>::infinity();
  /// The median of what the chain adds to each view's own PnP fit,
  /// √(RMS² − PnP RMS²): the misfit of the records alone.
  double median_excess_px = std::numeric_limits<double>::infinity();
  int cameras = 0;  ///< cameras the closed form solved
  int views = 0;    ///< views in the median
  /// Per solved camera: |t| of T_mount_cam and of T_holder_target, metres.
  std::vector<double> camera_lever_m, target_lever_m;
};

/// The views the hypotheses are scored on: per camera with enough views, up
/// to kScoredViews spread over them, none at the first or last pose so that
/// each shifted record set pairs every one of them.
Problem ScoringProblem(const Problem& problem) {
  Problem scoring;
  scoring.dataset = problem.dataset;
  scoring.T_mount_holder = problem.T_mount_holder;
  scoring.camera_views.resize(problem.camera_views.size());
  const int last_pose = static_cast<int>(problem.T_mount_holder.size()) - 1;
  for (size_t k = 0; k < problem.camera_views.size(); ++k) {
    std::vector<int> inner;
    for (int v : problem.camera_views[k])
      if (problem.views[v].pose > 0 && problem.views[v].pose < last_pose &&
          problem.views[v].T_cam_target)
        inner.push_back(v);
    if (inner.size() < kMinScoredViews) continue;
    const size_t n = std::min(inner.size(), kScoredViews);
    for (size_t i = 0; i < n; ++i) {
      scoring.camera_views[k].push_back(static_cast<int>(scoring.views.size()));
      scoring.views.push_back(problem.views[inner[i * inner.size() / n]]);
    }
  }
  return scoring;
}

/// The records under `h` scored on `scoring`: a closed form per camera (the
/// better of Park and Tsai, on a dozen diverse views; ViSP's, which the
/// initialisation also tries, was half of the CPU of a METRIC solve here, one
/// call at a time under its lock), with `refine` each camera's reprojection
/// solve from it (the robot exact, least squares), then the median over the
/// scored views of their RMS through that camera's chain.
Score ScoreOf(Problem scoring, const Hypothesis& h, bool refine = false) {
  const Dataset& dataset = *scoring.dataset;
  const SetupFrames frames = FramesOf(dataset.setup);
  const int num_poses = static_cast<int>(dataset.poses.size());
  for (int j = 0; j < num_poses; ++j) {
    const int record = std::clamp(j + h.shift, 0, num_poses - 1);
    scoring.T_mount_holder[j] =
        frames.MountFromHolder(Repaired(dataset.poses[record].T_base_ee, h));
  }
  const Problem diverse = WithDiverseViews(scoring, 12);
  const size_t num_cameras = scoring.camera_views.size();
  std::vector<std::optional<Eigen::Isometry3d>> T_cam_mount(num_cameras);
  std::vector<Eigen::Isometry3d> T_holder_target(num_cameras, Eigen::Isometry3d::Identity());
  for (size_t k = 0; k < num_cameras; ++k) {
    if (scoring.camera_views[k].empty()) continue;
    std::string chosen, why;
    const auto solved = SilentClosedFormHandEye(diverse, static_cast<int>(k), &chosen, &why,
                                                ClosedForms::kOpenCvOnly);
    if (!solved) continue;
    T_cam_mount[k] = solved->first;
    T_holder_target[k] = solved->second;
  }
  if (refine) {
    const Refinement refined =
        RefinePerCamera(scoring, T_cam_mount, T_holder_target, CalibrationOptions{});
    for (size_t k = 0; k < num_cameras; ++k)
      if (T_cam_mount[k] && refined.T_cam_mount[k]) {
        T_cam_mount[k] = refined.T_cam_mount[k];
        T_holder_target[k] = refined.T_holder_target[k];
      }
  }
  Score score;
  std::vector<double> rms, excess;
  for (size_t k = 0; k < num_cameras; ++k) {
    if (!T_cam_mount[k]) continue;
    ++score.cameras;
    score.camera_lever_m.push_back(T_cam_mount[k]->inverse().translation().norm());
    score.target_lever_m.push_back(T_holder_target[k].translation().norm());
    for (int v : scoring.camera_views[k]) {
      const View& view = scoring.views[v];
      rms.push_back(ViewRms(ViewErrors(scoring, view, *T_cam_mount[k], T_holder_target[k])));
      excess.push_back(std::sqrt(std::max(0.0, rms.back() * rms.back() - view.pnp_rms_px * view.pnp_rms_px)));
    }
  }
  if (rms.empty()) return score;
  score.views = static_cast<int>(rms.size());
  score.median_rms_px = Median(std::move(rms));
  score.median_excess_px = Median(std::move(excess));
  return score;
}

/// The factor by which the target's motions, as the cameras see them, exceed
/// the robot's: the translation along the rotation axis of a motion is the
/// same in every frame (conjugation keeps it), so on consistent records the
/// camera's and the robot's agree whatever the hand-eye transforms are. A
/// target declared smaller than printed makes PnP put it nearer, and every
/// camera motion shorter, by the same factor. nullopt with too few motions
/// that turn enough to have an axis, or whose angles disagree.
std::optional<double> MotionScale(const Problem& scoring) {
  std::vector<std::pair<double, double>> along;  // (robot, camera) translation along the axis, m
  for (const std::vector<int>& ids : scoring.camera_views)
    for (size_t a = 0; a < ids.size(); ++a)
      for (size_t b = a + 1; b < ids.size(); ++b) {
        const View& va = scoring.views[ids[a]];
        const View& vb = scoring.views[ids[b]];
        const Eigen::Isometry3d seen = *va.T_cam_target * vb.T_cam_target->inverse();
        const Eigen::Isometry3d moved =
            scoring.T_mount_holder[va.pose] * scoring.T_mount_holder[vb.pose].inverse();
        const Eigen::Vector3d w_seen = RotationVectorFromMatrix(seen.linear());
        const Eigen::Vector3d w_moved = RotationVectorFromMatrix(moved.linear());
        if (std::min(w_seen.norm(), w_moved.norm()) < 10.0 * kDeg) continue;
        if (std::abs(w_seen.norm() - w_moved.norm()) > 1.0 * kDeg) continue;
        along.emplace_back(moved.translation().dot(w_moved.normalized()),
                           seen.translation().dot(w_seen.normalized()));
      }
  if (along.size() < 8) return std::nullopt;
  // The half that moves most along its axis: a ratio of small shifts is noise.
  std::sort(along.begin(), along.end(),
            [](const auto& x, const auto& y) { return std::abs(x.first) > std::abs(y.first); });
  std::vector<double> ratios;
  for (size_t i = 0; i < along.size() / 2; ++i)
    if (along[i].first != 0.0) ratios.push_back(along[i].second / along[i].first);
  const double scale = Median(ratios);
  if (!(scale > 0) || !std::isfinite(scale)) return std::nullopt;
  return scale;
}

/// The hypotheses worth scoring: every discrete mistake, and the target scale
/// the motions show when it is clearly not 1 (nor a unit's 1000).
std::vector<Hypothesis> Hypotheses(const Problem& scoring) {
  std::vector<Hypothesis> out = {{Mistake::kInverted},
                                 {Mistake::kTransposed},
                                 {Mistake::kXyzwReadAsWxyz},
                                 {Mistake::kWxyzReadAsXyzw},
                                 {Mistake::kTranslationScale, 1000.0},
                                 {Mistake::kTranslationScale, 0.001},
                                 {Mistake::kShifted, 1.0, 1},
                                 {Mistake::kShifted, 1.0, -1}};
  if (const auto scale = MotionScale(scoring)) {
    const double off = std::abs(std::log(*scale));
    if (off > std::log(1.03) && std::abs(off - std::log(1000.0)) > std::log(2.0))
      out.push_back({Mistake::kTargetScale, *scale});
  }
  return out;
}

/// The target scale of `*h` (MotionScale's) moved to where the closed forms
/// explain the views best: PnP's poses through a lens model the images do
/// not follow move the motions' scale too (a rendered camera whose
/// distortion was left out: 0.957 on correct records, 1.051 on records of a
/// target declared 1.099× small). A grid of ±10 % in steps of 2 %, then the
/// vertex of the parabola through the best point and its neighbours.
void FitTargetScale(const Problem& scoring, int threads, Hypothesis* h, Score* score) {
  constexpr int kSteps = 5;
  constexpr double kStep = 0.02;
  const double centre = std::log(h->scale);
  std::vector<Hypothesis> grid(2 * kSteps + 1, *h);
  std::vector<Score> scores(grid.size());
  for (int i = 0; i < static_cast<int>(grid.size()); ++i)
    grid[i].scale = std::exp(centre + (i - kSteps) * kStep);
  ParallelFor(grid.size(), threads, [&](std::size_t i) { scores[i] = ScoreOf(scoring, grid[i]); });
  int best = kSteps;
  for (int i = 0; i < static_cast<int>(grid.size()); ++i)
    if (scores[i].cameras >= scores[best].cameras && scores[i].median_rms_px < scores[best].median_rms_px)
      best = i;
  *h = grid[best];
  *score = scores[best];
  if (best == 0 || best == 2 * kSteps) return;
  const double a = scores[best - 1].median_rms_px, b = scores[best].median_rms_px,
               c = scores[best + 1].median_rms_px;
  const double curvature = a - 2 * b + c;
  if (!(curvature > 0) || !std::isfinite(curvature)) return;
  Hypothesis vertex = *h;
  vertex.scale = std::exp(std::log(h->scale) + 0.5 * kStep * (a - c) / curvature);
  const Score at_vertex = ScoreOf(scoring, vertex);
  if (at_vertex.cameras >= score->cameras && at_vertex.median_rms_px < score->median_rms_px) {
    *h = vertex;
    *score = at_vertex;
  }
}

/// The target scale of `*h` moved to where refined chains (ScoreOf's
/// `refine`) explain the views best: ±4 % in steps of 1 % (the closed forms'
/// best lay 1.8 % from the truth on a rendered camera without its distortion).
void RefineTargetScale(const Problem& scoring, int threads, Hypothesis* h, Score* score) {
  constexpr int kSteps = 4;
  constexpr double kStep = 0.01;
  std::vector<Hypothesis> grid(2 * kSteps + 1, *h);
  std::vector<Score> scores(grid.size());
  for (int i = 0; i < static_cast<int>(grid.size()); ++i)
    grid[i].scale = h->scale * std::exp((i - kSteps) * kStep);
  ParallelFor(grid.size(), threads, [&](std::size_t i) { scores[i] = ScoreOf(scoring, grid[i], true); });
  for (size_t i = 0; i < grid.size(); ++i)
    if (scores[i].cameras >= score->cameras && scores[i].median_rms_px < score->median_rms_px) {
      *h = grid[i];
      *score = scores[i];
    }
}

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

void CheckRobotSigma(const RobotPrior& robot) {
  // The σ the solved pose blocks show where it was settled, else the prior's.
  const double sigma_m = robot.settled_sigma_m > 0 ? robot.settled_sigma_m : robot.sigma_m;
  const double sigma_rad = robot.settled_sigma_rad > 0 ? robot.settled_sigma_rad : robot.sigma_rad;
  const double mm = sigma_m * 1000.0, deg = sigma_rad / kDeg;
  if (mm <= kMaxRobotSigmaMm && deg <= kMaxRobotSigmaDeg) return;
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
