// SPDX-License-Identifier: GPL-2.0-or-later
// 180°-ambiguous checkerboards (core/src/half_turn.cc) on their own: the half
// turn of a board, a view numbered the other way round, and the numbering of
// a whole capture made alike from the robot's motions.
// clang-format off
// Before Catch, so that CHECK is Catch's, not glog's (which Ceres' headers define).
#include "problem.h"
// clang-format on
#include "half_turn.h"

#include <catch2/catch.hpp>
#include <map>
#include <set>

#include "handeye/core/checkerboard.h"
#include "support/projected_scene.h"

using namespace handeye;

namespace {

/// A projected cell with a 7 x 5 board (cols + rows even: ambiguous).
SyntheticScene AmbiguousScene(int cameras, std::uint64_t seed) {
  SceneOptions options;
  options.cell = "small";
  options.num_cameras = cameras;
  options.num_poses = 14;
  options.seed = seed;
  return test::ProjectedScene(options, 0.1, 5);
}

/// Renumbers an observation as a detector that took the opposite corner for
/// corner 0 would: id → N − 1 − id, the pixels unchanged.
void NumberRound(Observation* obs, int num_points) {
  for (int& id : obs->ids) id = num_points - 1 - id;
}

}  // namespace

TEST_CASE("the half turn of a board maps each corner onto its partner, and only where it is one",
          "[half_turn]") {
  const CheckerboardTarget ambiguous(7, 5, 0.03);  // 7 + 5 even
  const auto F = internal::HalfTurnSymmetry(ambiguous);
  REQUIRE(F);
  const auto& points = ambiguous.Points();
  const int n = static_cast<int>(points.size());
  REQUIRE(n == 35);
  for (int id = 0; id < n; ++id) {
    INFO("id " << id);
    CHECK((*F * points[id].p_target - points[n - 1 - id].p_target).norm() < 1e-12);
  }
  CHECK((*F * *F).isApprox(Eigen::Isometry3d::Identity(), 1e-15));  // a half turn twice
  CHECK(F->linear().determinant() == Approx(1.0));                  // a rotation, not a mirror
  CHECK_FALSE(internal::HalfTurnSymmetry(CheckerboardTarget(7, 6, 0.03)));  // 7 + 6 odd
}

TEST_CASE("a view numbered the other way round keeps its pixels and its pose as seen",
          "[half_turn]") {
  const SyntheticScene scene = AmbiguousScene(1, 3);
  const Eigen::Isometry3d F = *internal::HalfTurnSymmetry(*scene.dataset.target);
  internal::Problem problem = internal::BuildProblem(scene.dataset, CalibrationOptions{});
  internal::View& view = problem.views.front();
  REQUIRE(view.T_cam_target);
  const internal::View before = view;
  internal::FlipView(F, &view);
  CHECK(view.flipped);
  for (size_t p = 0; p < view.p_target.size(); ++p) {
    // Every point is where it was in the camera: the pose turned with the numbering.
    const Eigen::Vector3d seen_before = *before.T_cam_target * before.p_target[p];
    const Eigen::Vector3d seen_now = *view.T_cam_target * view.p_target[p];
    CHECK((seen_now - seen_before).norm() < 1e-12);
  }
  CHECK_FALSE(view.T_cam_target->isApprox(*before.T_cam_target, 1e-6));
  internal::FlipView(F, &view);  // twice: as it was
  CHECK_FALSE(view.flipped);
  CHECK(view.T_cam_target->isApprox(*before.T_cam_target, 1e-12));
  for (size_t p = 0; p < view.p_target.size(); ++p)
    CHECK((view.p_target[p] - before.p_target[p]).norm() < 1e-12);
}

TEST_CASE("views numbered half a turn round are found from the robot's motions and turned back",
          "[half_turn]") {
  for (const std::uint64_t seed : {5, 6, 7}) {
    SyntheticScene scene = AmbiguousScene(3, seed);
    const int n = static_cast<int>(scene.dataset.target->Points().size());
    // A few views per camera numbered round, as a detector would on a board it sees turned.
    std::set<std::pair<std::string, std::string>> round;  // (camera, pose)
    std::map<std::string, int> per_camera;
    for (Observation& obs : scene.dataset.observations)
      if (obs.ids.size() == static_cast<size_t>(n) && per_camera[obs.camera]++ % 3 == 1) {
        NumberRound(&obs, n);
        round.insert({obs.camera, obs.pose_id});
      }
    REQUIRE(round.size() >= 4);
    internal::Problem problem = internal::BuildProblem(scene.dataset, CalibrationOptions{});
    const Eigen::Isometry3d F = *internal::HalfTurnSymmetry(*scene.dataset.target);
    const int flipped = internal::NumberViewsAlike(&problem, F);
    INFO("seed " << seed);
    // The fewer views turn: exactly those numbered round.
    CHECK(flipped == static_cast<int>(round.size()));
    for (const internal::View& view : problem.views) {
      if (!view.used) continue;
      const bool was_round = round.count({view.observation->camera, view.observation->pose_id}) > 0;
      CHECK(view.flipped == was_round);
    }
    // Numbered alike, every view's pose of the target agrees with the truth's numbering:
    // the target's motion between two views of a camera is the robot's.
    const SyntheticScene truth = AmbiguousScene(3, seed);  // the problem points into it
    internal::Problem clean = internal::BuildProblem(truth.dataset, CalibrationOptions{});
    for (size_t v = 0; v < problem.views.size(); ++v) {
      if (!problem.views[v].used || !clean.views[v].T_cam_target) continue;
      CHECK(problem.views[v].T_cam_target->isApprox(*clean.views[v].T_cam_target, 1e-6));
    }
  }
}

TEST_CASE("a capture numbered alike is left as it is", "[half_turn]") {
  const SyntheticScene scene = AmbiguousScene(3, 9);  // the problem points into it
  internal::Problem problem = internal::BuildProblem(scene.dataset, CalibrationOptions{});
  const Eigen::Isometry3d F = *internal::HalfTurnSymmetry(*problem.dataset->target);
  CHECK(internal::NumberViewsAlike(&problem, F) == 0);
  for (const internal::View& view : problem.views) CHECK_FALSE(view.flipped);
}
