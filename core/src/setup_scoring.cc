// SPDX-License-Identifier: GPL-2.0-or-later
// The setup-mistake detective's hypotheses and their scores (setup_scoring.h).
#include "setup_scoring.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "closed_form.h"
#include "diagnostics_internal.h"
#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"
#include "parallel.h"
#include "refinement.h"
#include "residuals.h"

namespace handeye::internal {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// Views scored per camera (spread over its views): enough for a median,
/// few enough to keep METRIC's 4 × 250 views well under a second.
constexpr size_t kScoredViews = 40;

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

}  // namespace

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
Score ScoreOf(Problem scoring, const Hypothesis& h, bool refine) {
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

}  // namespace handeye::internal
