// SPDX-License-Identifier: GPL-2.0-or-later
// Which views to trust (core/src/view_consensus.cc) on their own, against
// the truth of simulated cells: the robot-motion vote, the views off a
// solution, the warnings on robot records, the noise the residuals show and
// the robot's error the views show.
#include "view_consensus.h"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <set>
#include <string>

#include "handeye/core/error.h"
#include "motion_diversity.h"
#include "problem.h"
#include "residuals.h"
#include "robot_error.h"
#include "support/problem_cell.h"

using namespace handeye;
using test::ProblemCell;
using test::SmallCell;

namespace {

/// Every camera's T_holder_target: the true one.
internal::TargetPoses TrueTargets(const ProblemCell& cell) {
  return internal::TargetPoses(cell.scene.dataset.cameras.size(), cell.TrueHolderTarget());
}

/// The ids of the poses whose records were exchanged.
std::set<std::string> SwappedPoses(const SyntheticScene& scene) {
  std::set<std::string> swapped;
  for (const auto& [a, b] : scene.swapped_poses) swapped.insert({a, b});
  return swapped;
}

}  // namespace

TEST_CASE("the motion vote leaves no view of a clean cell out, even with an inexact robot",
          "[view_consensus]") {
  for (const Setup setup : test::kBothSetups)
    for (const std::uint64_t seed : {1, 2, 3})
      for (const double robot : {0.0, 1.0}) {
        SceneOptions options = SmallCell(setup, 3, 16, seed);
        options.pose_noise_mm = 0.3 * robot;
        options.pose_noise_deg = 0.03 * robot;
        ProblemCell cell(options, 0.2);
        INFO(SetupName(setup) << ", seed " << seed << ", robot noise " << robot);
        const int used = test::UsedViews(cell.problem);
        CHECK(internal::RejectInconsistentMotions(&cell.problem) == 0);
        CHECK(test::UsedViews(cell.problem) == used);
      }
}

TEST_CASE("a view the vote leaves out whose pose another camera confirms is named, not its record",
          "[view_consensus]") {
  // One view's PnP pose turned by 3 deg (a board partly hidden, glare): its
  // camera's vote leaves it out, but the other cameras that see the same
  // pose find its record agree with their own views, so the record holds.
  for (const std::uint64_t seed : {1, 2, 3}) {
    ProblemCell cell(SmallCell(Setup::kEyeToHand, 3, 16, seed), 0.2);
    INFO("seed " << seed);
    int spoiled = -1;
    for (size_t i = 0; i < cell.problem.views.size() && spoiled < 0; ++i) {
      const internal::View& view = cell.problem.views[i];
      int others = 0;
      for (const internal::View& other : cell.problem.views)
        others += other.pose == view.pose && other.camera != view.camera && other.T_cam_target;
      if (view.T_cam_target && others > 0) spoiled = static_cast<int>(i);
    }
    REQUIRE(spoiled >= 0);
    internal::View& view = cell.problem.views[spoiled];
    view.T_cam_target->linear() =
        (Eigen::AngleAxisd(3.0 * M_PI / 180.0, Eigen::Vector3d(1, 1, 0).normalized()) *
         view.T_cam_target->rotation())
            .eval();
    CHECK(internal::RejectInconsistentMotions(&cell.problem) == 1);
    CHECK_FALSE(view.used);
    CHECK_THAT(view.rejected_because,
               Catch::Contains("finds the same robot record agree with its own views: the record "
                               "holds, and this view's corners or the pose they give are off"));
    CHECK_THAT(view.rejected_because, !Catch::Contains("likely belongs to another pose"));
    CHECK(internal::PoseRecordWarnings(cell.problem, cell.TrueCamMounts(), TrueTargets(cell))
              .empty());
  }
}

TEST_CASE("the motion vote leaves out the views of records swapped between poses, and no other",
          "[view_consensus]") {
  for (const Setup setup : test::kBothSetups)
    for (const std::uint64_t seed : {1, 2, 3}) {
      SceneOptions options = SmallCell(setup, 3, 16, seed);
      options.swap_poses = 1;
      ProblemCell cell(options, 0.2);
      const std::set<std::string> swapped = SwappedPoses(cell.scene);
      REQUIRE(swapped.size() == 2);
      INFO(SetupName(setup) << ", seed " << seed);
      const int rejected = internal::RejectInconsistentMotions(&cell.problem);
      int inconsistent = 0;
      for (const internal::View& view : cell.problem.views) {
        const std::string& pose = view.observation->pose_id;
        INFO("view of pose " << pose << " by " << view.observation->camera);
        if (!view.T_cam_target) continue;  // PnP failed: not the vote's
        CHECK(view.inconsistent == (swapped.count(pose) == 1));
        CHECK(view.used == !view.inconsistent);
        if (view.inconsistent) {
          ++inconsistent;
          CHECK_THAT(view.rejected_because,
                     Catch::Contains("the robot record likely belongs to another pose"));
        }
      }
      CHECK(rejected == inconsistent);
      CHECK(rejected >= 2);
      // The used-view index no longer holds them.
      for (const auto& ids : cell.problem.camera_views)
        for (int v : ids) CHECK_FALSE(cell.problem.views[v].inconsistent);

      // Each swapped pose is named once, with the displacement its record
      // gives; the truth solution names no other.
      const auto warnings =
          internal::PoseRecordWarnings(cell.problem, cell.TrueCamMounts(), TrueTargets(cell));
      std::set<std::string> named;
      for (const Warning& w : warnings) {
        CHECK(w.kind == WarningKind::kPoseRecordMismatch);
        CHECK_THAT(w.text, Catch::Contains("its robot record disagrees with") &&
                               Catch::Contains(" mm: the image and the pose likely do not belong"));
        named.insert(w.pose);
      }
      CHECK(named == swapped);
      CHECK(warnings.size() == 2);
    }
}

TEST_CASE("views off the solution: none at the truth, a view moved by pixels is named",
          "[view_consensus]") {
  for (const Setup setup : test::kBothSetups) {
    ProblemCell cell(SmallCell(setup, 2, 14, 4), 0.2);
    INFO(SetupName(setup));
    const auto T_cam_mount = cell.TrueCamMounts();
    CHECK(internal::ViewsOffTheSolution(cell.problem, T_cam_mount, TrueTargets(cell)).empty());
    // Through the truth a view's RMS is ≈ 0.28 px (0.2 px per axis): 3 px
    // off is far outside; 0.6 px off is within four times the median RMS.
    const int far = cell.problem.camera_views[0][2];
    const int near = cell.problem.camera_views[1][3];
    auto shift = [&](int v, double px) {
      // The view reads its observation in the scene's dataset.
      const auto i = cell.problem.views[v].observation - cell.scene.dataset.observations.data();
      for (Eigen::Vector2d& p : cell.scene.dataset.observations[i].points_px) p.x() += px;
    };
    shift(far, 3.0);
    shift(near, 0.6);
    CHECK(internal::ViewsOffTheSolution(cell.problem, T_cam_mount, TrueTargets(cell)) ==
          std::vector<int>{far});
    // A camera without a solution is not judged.
    std::vector<std::optional<Eigen::Isometry3d>> only_second = T_cam_mount;
    only_second[0].reset();
    CHECK(internal::ViewsOffTheSolution(cell.problem, only_second, TrueTargets(cell)).empty());
  }
}

TEST_CASE(
    "an inconsistent view that fits with the target turned over is said to be seen from behind",
    "[view_consensus]") {
  ProblemCell cell(SmallCell(Setup::kEyeToHand, 2, 12, 15), 0.0);
  const auto T_cam_mount = cell.TrueCamMounts();
  const std::vector<int>& ids = cell.problem.camera_views[0];
  REQUIRE(ids.size() >= 3);
  // Three views left out by the vote, their PnP poses turned half a turn
  // about the board's x axis (over: from behind), its normal (round: a
  // numbering), and not at all.
  const int over = ids[0], round = ids[1], kept = ids[2];
  auto turn = [&](int v, const Eigen::Vector3d& axis) {
    internal::View& view = cell.problem.views[v];
    Eigen::Isometry3d half = Eigen::Isometry3d::Identity();
    half.linear() = MatrixFromRotationVector(M_PI * axis);
    *view.T_cam_target = *view.T_cam_target * half;
  };
  turn(over, Eigen::Vector3d::UnitX());
  turn(round, Eigen::Vector3d::UnitZ());
  for (int v : {over, round, kept}) {
    cell.problem.views[v].inconsistent = true;
    cell.problem.views[v].rejected_because = "the vote";
  }
  internal::ExplainInconsistentViews(&cell.problem, T_cam_mount, TrueTargets(cell));
  CHECK_FALSE(cell.problem.views[over].inconsistent);
  CHECK_THAT(cell.problem.views[over].rejected_because,
             Catch::StartsWith("the target is seen from behind, its pattern mirrored"));
  for (int v : {round, kept}) {
    CHECK(cell.problem.views[v].inconsistent);
    CHECK(cell.problem.views[v].rejected_because == "the vote");
  }
  // A camera without a solution explains nothing.
  cell.problem.views[over].inconsistent = true;
  std::vector<std::optional<Eigen::Isometry3d>> none(2);
  internal::ExplainInconsistentViews(&cell.problem, none, TrueTargets(cell));
  CHECK(cell.problem.views[over].inconsistent);
}

TEST_CASE("the residuals through the truth and the PnP fits both give the detection noise",
          "[view_consensus]") {
  for (const double noise_px : {0.1, 0.3, 1.0}) {
    const ProblemCell cell(SmallCell(Setup::kEyeToHand, 3, 16, 5), noise_px);
    INFO("noise " << noise_px << " px");
    const double residual =
        internal::ResidualSigmaPx(cell.problem, cell.TrueCamMounts(), TrueTargets(cell));
    // Measured: within 0.6 %.
    CHECK(residual == Approx(noise_px).epsilon(0.03));
    CHECK(internal::DetectionSigmaPx(cell.problem) == Approx(noise_px).epsilon(0.03));
  }
  // Noise-free, the PnP fits leave nothing: the floor.
  const ProblemCell exact(SmallCell(Setup::kEyeToHand, 2, 12, 5), 0.0);
  CHECK(internal::DetectionSigmaPx(exact.problem) == 1e-3);
}

TEST_CASE("the robot's error the views show: none for an exact robot, near the simulated one",
          "[view_consensus]") {
  for (const Setup setup : test::kBothSetups) {
    INFO(SetupName(setup));
    for (const std::uint64_t seed : {6, 7, 8}) {
      const ProblemCell exact(SmallCell(setup, 3, 20, seed), 0.1);
      // None, or residuals not clearly above PnP's (which the solve then weighs).
      const auto none =
          internal::EstimateRobotPrior(exact.problem, exact.TrueCamMounts(), TrueTargets(exact));
      CHECK((!none || none->chain_to_pnp < internal::kClearChainToPnp));
      SceneOptions options = SmallCell(setup, 3, 20, seed);
      options.pose_noise_mm = 0.3;
      options.pose_noise_deg = 0.03;
      const ProblemCell noisy(options, 0.1);
      const auto prior =
          internal::EstimateRobotPrior(noisy.problem, noisy.TrueCamMounts(), TrueTargets(noisy));
      REQUIRE(prior);
      // Seeds 6-8, both setups: 0.22-0.93 mm, and 0-0.037 deg (the robot's σ
      // per axis: 0.3 mm, and 0.03 deg / √3 = 0.017 deg, the simulated turn
      // being about a random axis): on this cell a view's PnP turns the
      // target by more than the robot does, so the
      // rotation left beyond PnP's noise can be nothing (the floor, 1e-5 deg);
      // the flange's σ then still holds the rotation times the reach.
      CHECK(prior->chain_to_pnp > 1.2);
      CHECK(prior->pixel_sigma_px == Approx(0.1).epsilon(0.05));
      CHECK(prior->sigma_m * 1000 > 0.3 / 4);
      CHECK(prior->sigma_m * 1000 < 0.3 * 4);
      CHECK(prior->sigma_rad * 180 / M_PI < 0.03 * 3);
    }
  }
}

TEST_CASE("robot motions about one axis, or too small, cannot give the target",
          "[view_consensus]") {
  ProblemCell cell(SmallCell(Setup::kEyeToHand, 2, 12, 7), 0.0);
  CHECK_NOTHROW(internal::CheckMotionDiversity(cell.problem));
  internal::Problem one_axis = cell.problem;
  internal::Problem still = cell.problem;
  for (size_t j = 0; j < one_axis.T_mount_holder.size(); ++j) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = MatrixFromRotationVector(Eigen::Vector3d(0.1, 0.2, 0.9).normalized() * 0.2 * j);
    T.translation() = Eigen::Vector3d(0.4, 0.1 * j, 0.3);
    one_axis.T_mount_holder[j] = T;
    T.linear() = MatrixFromRotationVector(Eigen::Vector3d(j % 2, 1, 0) * 1e-3);
    still.T_mount_holder[j] = T;
  }
  CHECK_THROWS_WITH(internal::CheckMotionDiversity(one_axis),
                    Catch::Contains("every motion between the views rotates about the same axis"));
  CHECK_THROWS_AS(internal::CheckMotionDiversity(still), SolveError);
  CHECK_THAT(internal::MotionDiversityProblem(still, {0}),
             Catch::StartsWith("degenerate robot motion: the views differ in rotation by at most"));
  // Camera 1 alone is judged by its own views: those of one_axis are degenerate too.
  CHECK_FALSE(internal::MotionDiversityProblem(one_axis, {1}).empty());
  CHECK(internal::MotionDiversityProblem(cell.problem, {1}).empty());
}
