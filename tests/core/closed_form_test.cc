// SPDX-License-Identifier: GPL-2.0-or-later
// The closed forms (core/src/closed_form.cc) on their own, against the truth
// of projected cells: every baseline method in both setups, the two
// one-unknown-given-the-other consensus steps, the silent candidates of the
// joint solve's start, the shared-target form and the view thinning.
#include "closed_form.h"

#include <catch2/catch.hpp>
#include <iostream>
#include <set>
#include <sstream>
#include <string>

#include "handeye/core/transform.h"
#include "pose_consensus.h"
#include "problem.h"
#include "support/projected_scene.h"

using namespace handeye;

namespace {

double Mm(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return 1000.0 * (a.translation() - b.translation()).norm();
}
double Deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return RotationDistance(a.rotation(), b.rotation()) * 180.0 / M_PI;
}

/// The truth in the solver's frames: T_cam_mount of camera k, T_holder_target.
Eigen::Isometry3d TrueCamMount(const SyntheticScene& scene, int k) {
  return scene.truth.T_cam.at(scene.dataset.cameras[k].name).inverse();
}

struct Cell {
  SyntheticScene scene;
  internal::Problem problem;
};

/// A projected cell's problem; the problem points into the scene, so both live together.
std::unique_ptr<Cell> MakeCell(Setup setup, double noise_px, std::uint64_t seed = 4,
                               double robot_mm = 0, double robot_deg = 0) {
  SceneOptions options;
  options.cell = "small";
  options.num_cameras = 2;
  options.num_poses = 14;
  options.seed = seed;
  options.setup = setup;
  options.pose_noise_mm = robot_mm;
  options.pose_noise_deg = robot_deg;
  auto cell = std::make_unique<Cell>();
  cell->scene = test::ProjectedScene(options, noise_px);
  cell->problem = internal::BuildProblem(cell->scene.dataset, CalibrationOptions{});
  return cell;
}

}  // namespace

TEST_CASE("every baseline closed form recovers camera and target from exact views, in both setups",
          "[closed_form]") {
  for (const Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    const auto cell = MakeCell(setup, 0.0);
    for (const Method method : {Method::kTsai, Method::kPark, Method::kHoraud, Method::kAndreff,
                                Method::kDaniilidis, Method::kShah, Method::kLi, Method::kVisp}) {
      for (int k = 0; k < 2; ++k) {
        INFO(SetupName(setup) << ", " << MethodName(method) << ", camera " << k);
        std::string why;
        std::ostringstream silenced;  // ViSP prints its own figures
        std::streambuf* out = std::cout.rdbuf(silenced.rdbuf());
        const auto solved = internal::ClosedFormHandEye(cell->problem, k, method, &why);
        std::cout.rdbuf(out);
        INFO(why);
        REQUIRE(solved);
        CHECK(Mm(solved->first, TrueCamMount(cell->scene, k)) < 0.01);
        CHECK(Deg(solved->first, TrueCamMount(cell->scene, k)) < 1e-4);
        CHECK(Mm(solved->second, cell->scene.truth.T_target) < 0.01);
      }
    }
  }
}

TEST_CASE("closed forms on noisy views and robot records stay near the truth", "[closed_form]") {
  const auto cell = MakeCell(Setup::kEyeToHand, 0.2, 8, 0.1, 0.01);
  for (const Method method : {Method::kTsai, Method::kPark, Method::kDaniilidis}) {
    for (int k = 0; k < 2; ++k) {
      INFO(MethodName(method) << ", camera " << k);
      std::string why;
      const auto solved = internal::ClosedFormHandEye(cell->problem, k, method, &why);
      REQUIRE(solved);
      // A small cell (about 1.5 m) with 0.2 px and a 0.1 mm / 0.01° robot:
      // closed forms are millimetres off, not centimetres.
      CHECK(Mm(solved->first, TrueCamMount(cell->scene, k)) < 10.0);
      CHECK(Deg(solved->first, TrueCamMount(cell->scene, k)) < 0.3);
    }
  }
}

TEST_CASE("one unknown given the other: camera from target and target from camera",
          "[closed_form]") {
  for (const Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    const auto cell = MakeCell(setup, 0.0);
    for (int k = 0; k < 2; ++k) {
      INFO(SetupName(setup) << ", camera " << k);
      const auto camera = internal::CameraGivenTarget(cell->problem, k, cell->scene.truth.T_target);
      REQUIRE(camera);
      CHECK(Mm(*camera, TrueCamMount(cell->scene, k)) < 1e-3);
      CHECK(Deg(*camera, TrueCamMount(cell->scene, k)) < 1e-6);
      const auto target =
          internal::TargetGivenCamera(cell->problem, k, TrueCamMount(cell->scene, k));
      REQUIRE(target);
      CHECK(Mm(*target, cell->scene.truth.T_target) < 1e-3);
      CHECK(Deg(*target, cell->scene.truth.T_target) < 1e-6);
    }
  }
}

TEST_CASE("the joint solve's candidates are Park, Tsai and ViSP, and print nothing",
          "[closed_form]") {
  const auto cell = MakeCell(Setup::kEyeToHand, 0.1);
  std::ostringstream printed;
  std::streambuf* out = std::cout.rdbuf(printed.rdbuf());
  std::string why, chosen;
  const std::vector<internal::NamedClosedForm> all =
      internal::SilentClosedForms(cell->problem, 0, &why);
  const auto best = internal::SilentClosedFormHandEye(cell->problem, 0, &chosen, &why);
  std::cout.rdbuf(out);
  CHECK(printed.str().empty());
  std::set<std::string> methods;
  for (const auto& form : all) {
    methods.insert(form.method);
    CHECK(Mm(form.T_cam_mount, TrueCamMount(cell->scene, 0)) < 5.0);
  }
  CHECK(methods == std::set<std::string>{"park", "tsai", "visp"});
  REQUIRE(best);
  CHECK(methods.count(chosen) == 1);
  CHECK(Mm(best->first, TrueCamMount(cell->scene, 0)) < 5.0);
}

TEST_CASE("too few views: the closed forms say so instead of solving", "[closed_form]") {
  auto cell = MakeCell(Setup::kEyeToHand, 0.0);
  // Camera 0 left with two views: one motion, which no AX = XB determines.
  int kept = 0;
  for (internal::View& view : cell->problem.views)
    if (view.camera == 0 && view.used && ++kept > 2) view.used = false;
  internal::IndexUsedViews(&cell->problem);
  REQUIRE(cell->problem.camera_views[0].size() == 2);
  std::string why;
  CHECK_FALSE(internal::ClosedFormHandEye(cell->problem, 0, Method::kPark, &why));
  CHECK_FALSE(why.empty());
  why.clear();
  CHECK(internal::SilentClosedForms(cell->problem, 0, &why).empty());
  CHECK_FALSE(why.empty());
  // Camera 1 still solves.
  CHECK(internal::ClosedFormHandEye(cell->problem, 1, Method::kPark, &why));
}

TEST_CASE("the shared-target closed form takes the motions of all cameras at once",
          "[closed_form]") {
  for (const Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    const auto cell = MakeCell(setup, 0.0);
    INFO(SetupName(setup));
    const auto target = internal::SharedTargetClosedForm(cell->problem);
    REQUIRE(target);
    CHECK(Mm(*target, cell->scene.truth.T_target) < 0.01);
    CHECK(Deg(*target, cell->scene.truth.T_target) < 1e-4);
  }
}

TEST_CASE("thinning keeps at most the views asked, spread over the robot's rotations",
          "[closed_form]") {
  const auto cell = MakeCell(Setup::kEyeToHand, 0.0);
  for (const size_t max_views : {size_t{3}, size_t{6}, size_t{100}}) {
    const internal::Problem thin = internal::WithDiverseViews(cell->problem, max_views);
    for (size_t k = 0; k < 2; ++k) {
      INFO("max " << max_views << ", camera " << k);
      const size_t had = cell->problem.camera_views[k].size();
      CHECK(thin.camera_views[k].size() == std::min(had, max_views));
      std::set<int> poses;
      for (int v : thin.camera_views[k]) {
        CHECK(thin.views[v].used);
        CHECK(thin.views[v].camera == static_cast<int>(k));
        poses.insert(thin.views[v].pose);
      }
      CHECK(poses.size() == thin.camera_views[k].size());  // no view twice
    }
  }
  // Thinned to a few diverse views, a closed form still recovers the truth.
  const internal::Problem thin = internal::WithDiverseViews(cell->problem, 5);
  std::string why;
  const auto solved = internal::ClosedFormHandEye(thin, 0, Method::kPark, &why);
  REQUIRE(solved);
  CHECK(Mm(solved->first, TrueCamMount(cell->scene, 0)) < 0.01);
}
