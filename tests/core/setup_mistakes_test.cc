// SPDX-License-Identifier: GPL-2.0-or-later
// The setup-mistake detective (issue 24) on projected observations: each
// usual mistake made to a correct cell is named with its fix (SolveError, exit
// 3), and correct cells of every kind are never called mistaken.
#include "setup_mistakes.h"

#include <catch2/catch.hpp>
#include <functional>
#include <map>
#include <random>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/error.h"
#include "handeye/sim/synthetic.h"
#include "problem.h"

using namespace handeye;
using Catch::Matchers::Contains;

namespace {

SyntheticScene MistakeScene(Setup setup, std::uint64_t seed, int poses = 16, double robot_mm = 0.3,
                     double robot_deg = 0.03, int cameras = 3, const std::string& cell = "small",
                     int cols = 7) {
  SceneOptions options;
  options.cell = cell;
  options.setup = setup;
  options.num_cameras = cameras;
  options.num_poses = poses;
  options.seed = seed;
  options.pose_noise_mm = robot_mm;
  options.pose_noise_deg = robot_deg;
  SyntheticScene scene =
      MakeScene(options, std::make_shared<const CheckerboardTarget>(cols, 4, 0.04));
  std::mt19937_64 rng(seed * 17 + 3);
  AddProjectedObservations(&scene, 0.15, &rng);
  return scene;
}

// The judgement on a dataset, as Calibrate() makes it before the solve.
internal::SetupVerdict Judge(const Dataset& dataset) {
  const internal::Problem problem = internal::BuildProblem(dataset, CalibrationOptions());
  return internal::JudgeSetup(problem, 2);
}

// Calibrate() with default options must refuse with a message containing every `words`.
void RequireNamed(const Dataset& dataset, const std::vector<std::string>& words) {
  const internal::SetupVerdict verdict = Judge(dataset);
  INFO("as given " << verdict.given_px << " px, best repair '" << verdict.best << "' "
                   << verdict.best_px << " px");
  try {
    Calibrate(dataset, CalibrationOptions());
    FAIL("no SolveError");
  } catch (const SolveError& e) {
    INFO(e.what());
    for (const std::string& w : words) CHECK_THAT(e.what(), Contains(w));
  }
}

void ForEachPose(Dataset* dataset, const std::function<void(Eigen::Isometry3d*)>& change) {
  for (RobotPose& pose : dataset->poses) change(&pose.T_base_ee);
}

// The quaternion of T's rotation written as (a, b, c, d) and read back as (w, x, y, z).
void ReadQuaternion(Eigen::Isometry3d* T, bool xyzw_read_as_wxyz) {
  const Eigen::Quaterniond q(T->linear());
  const Eigen::Quaterniond read = xyzw_read_as_wxyz
                                      ? Eigen::Quaterniond(q.x(), q.y(), q.z(), q.w())
                                      : Eigen::Quaterniond(q.z(), q.w(), q.x(), q.y());
  T->linear() = read.normalized().toRotationMatrix();
}

}  // namespace

TEST_CASE("Robot poses inverted are named, with the setup swap that fits the same chain",
          "[calibration][setup]") {
  for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    SyntheticScene scene = MistakeScene(setup, 2);
    ForEachPose(&scene.dataset, [](Eigen::Isometry3d* T) { *T = T->inverse(); });
    RequireNamed(scene.dataset,
                 {"robot poses look inverted", "invert every pose", "--accept-setup"});
  }
}

TEST_CASE("The setup declared the other way round is named", "[calibration][setup]") {
  for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    SyntheticScene scene = MistakeScene(setup, 3);
    scene.dataset.setup = setup == Setup::kEyeToHand ? Setup::kEyeInHand : Setup::kEyeToHand;
    // The likelier reading comes first: here the setup, as the lever arms show.
    RequireNamed(scene.dataset,
                 {std::string("or the setup is ") + SetupName(setup), "; or, if your controller"});
  }
}

TEST_CASE("Robot rotations transposed are named", "[calibration][setup]") {
  SyntheticScene scene = MistakeScene(Setup::kEyeToHand, 4);
  ForEachPose(&scene.dataset,
              [](Eigen::Isometry3d* T) { T->linear() = T->linear().transpose().eval(); });
  RequireNamed(scene.dataset, {"rotations look transposed", "transpose the 3×3 rotation"});
}

TEST_CASE("Quaternions read in the wrong order are named, either way", "[calibration][setup]") {
  SyntheticScene xyzw = MistakeScene(Setup::kEyeToHand, 5);
  ForEachPose(&xyzw.dataset, [](Eigen::Isometry3d* T) { ReadQuaternion(T, true); });
  RequireNamed(xyzw.dataset, {"written x, y, z, w but read as w, x, y, z", "quaternion_xyzw"});
  SyntheticScene wxyz = MistakeScene(Setup::kEyeInHand, 6);
  ForEachPose(&wxyz.dataset, [](Eigen::Isometry3d* T) { ReadQuaternion(T, false); });
  RequireNamed(wxyz.dataset, {"written w, x, y, z but read as x, y, z, w", "quaternion_wxyz"});
}

TEST_CASE("Robot translations in the wrong unit are named, either way", "[calibration][setup]") {
  SyntheticScene metres_as_mm = MistakeScene(Setup::kEyeToHand, 7);
  ForEachPose(&metres_as_mm.dataset, [](Eigen::Isometry3d* T) { T->translation() /= 1000.0; });
  RequireNamed(metres_as_mm.dataset, {"1000× too small", "translation_m"});
  SyntheticScene mm_as_metres = MistakeScene(Setup::kEyeInHand, 8);
  ForEachPose(&mm_as_metres.dataset, [](Eigen::Isometry3d* T) { T->translation() *= 1000.0; });
  RequireNamed(mm_as_metres.dataset, {"1000× too large", "translation_mm"});
}

TEST_CASE("A target declared at the wrong size is named with the size it looks",
          "[calibration][setup]") {
  // Squares of 40 mm declared 32 mm, and declared 50 mm.
  for (double declared : {0.032, 0.05}) {
    SyntheticScene scene = MistakeScene(Setup::kEyeToHand, 9);
    scene.dataset.target = std::make_shared<const CheckerboardTarget>(7, 4, declared);
    RequireNamed(scene.dataset, {"the size declared", "square_size_m", "looks "});
    try {
      Calibrate(scene.dataset, CalibrationOptions());
    } catch (const SolveError& e) {
      const std::string message = e.what();
      const double looks_mm = std::stod(message.substr(message.find("mm, looks ") + 10));
      INFO(message);
      CHECK(std::abs(looks_mm - 40.0) < 0.5);
    }
  }
}

TEST_CASE("Images shifted against the robot poses by one are named, either way",
          "[calibration][setup]") {
  for (int shift : {1, -1}) {
    SyntheticScene scene = MistakeScene(Setup::kEyeToHand, 10, 18);
    std::vector<Eigen::Isometry3d> records;
    for (const RobotPose& pose : scene.dataset.poses) records.push_back(pose.T_base_ee);
    const int n = static_cast<int>(records.size());
    for (int j = 0; j < n; ++j) scene.dataset.poses[j].T_base_ee = records[(j + shift + n) % n];
    RequireNamed(scene.dataset, {"shifted against the robot poses by one",
                                 shift > 0 ? "listed before its own" : "listed after its own"});
  }
}

TEST_CASE("Repeated images: every image the same fails, one repeated image is left out and named",
          "[calibration][setup]") {
  SyntheticScene scene = MistakeScene(Setup::kEyeToHand, 11);
  Dataset all_same = scene.dataset;
  std::map<std::string, Observation> first;
  for (Observation& obs : all_same.observations) {
    if (!first.count(obs.camera)) first[obs.camera] = obs;
    obs.ids = first[obs.camera].ids;
    obs.points_px = first[obs.camera].points_px;
  }
  RequireNamed(all_same, {"repeat another view's detected points exactly",
                          "the same image under different robot poses"});

  Dataset one_copy = scene.dataset;
  Observation* a = &one_copy.observations[0];
  Observation* b = nullptr;
  for (Observation& obs : one_copy.observations)
    if (obs.camera == a->camera && obs.pose_id != a->pose_id) b = &obs;
  REQUIRE(b != nullptr);
  b->ids = a->ids;
  b->points_px = a->points_px;
  const CalibrationResult result = Calibrate(one_copy, CalibrationOptions());
  // One warning per left-out view, each naming the other pose, and saying
  // which view it is about in its fields too.
  int named = 0;
  for (const Warning& w : result.warnings) {
    if (w.text.find("detected points are identical") == std::string::npos) continue;
    ++named;
    const bool of_a = w.text.find("pose '" + a->pose_id + "'") != std::string::npos;
    CHECK_THAT(w.text, Contains("pose(s) '" + (of_a ? b->pose_id : a->pose_id) + "'"));
    CHECK(w.kind == WarningKind::kViewLeftOut);
    CHECK(w.camera == a->camera);
    CHECK(w.pose == (of_a ? a->pose_id : b->pose_id));
    REQUIRE(w.view);
    REQUIRE(*w.view < static_cast<int>(result.views.size()));
    CHECK(result.views[*w.view].pose_id == w.pose);
    CHECK(result.views[*w.view].camera == w.camera);
    CHECK_FALSE(result.views[*w.view].used);
  }
  CHECK(named == 2);
  for (const ViewResult& view : result.views)
    if (view.camera == a->camera && (view.pose_id == a->pose_id || view.pose_id == b->pose_id))
      CHECK_FALSE(view.used);
}

TEST_CASE("A robot error beyond any real robot's is refused unless the data are accepted",
          "[calibration][setup]") {
  // Records 8 mm / 0.8 deg off at random: no single mistake explains them.
  // With fewer poses than the model is otherwise chosen by (10) too: held-out
  // poses decide there, and the exact robot predicts them worse.
  SyntheticScene scene = MistakeScene(Setup::kEyeToHand, 12, 16, 8.0, 0.8);
  RequireNamed(scene.dataset,
               {"the robot's own pose error would have to be", "more than any industrial robot"});
  RequireNamed(MistakeScene(Setup::kEyeToHand, 12, 10, 8.0, 0.8).dataset,
               {"the robot's own pose error would have to be", "more than any industrial robot"});
  CalibrationOptions accept;
  accept.check_setup = false;
  CalibrationResult result;
  REQUIRE_NOTHROW(result = Calibrate(scene.dataset, accept));
  CHECK(result.solver.robot_sigma_mm > 5.0);
}

TEST_CASE("calibrate with --accept-setup takes a mistaken dataset as it is",
          "[calibration][setup]") {
  SyntheticScene scene = MistakeScene(Setup::kEyeToHand, 13);
  ForEachPose(&scene.dataset,
              [](Eigen::Isometry3d* T) { T->linear() = T->linear().transpose().eval(); });
  CalibrationOptions accept;
  accept.check_setup = false;
  accept.robot_sigma_mm = accept.robot_sigma_deg =
      0;  // a quick solve: only the detective is under test
  CHECK_NOTHROW(Calibrate(scene.dataset, accept));
}

TEST_CASE("Correct cells are never called mistaken", "[calibration][setup]") {
  // Robot error 0.3 mm / 0.03 deg and 1 mm / 0.1 deg, both setups, small and
  // medium cells, cameras with few views, a 180-degree ambiguous board with
  // two views numbered the other way round.
  int scenes = 0;
  double worst_ratio = 0;
  for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand})
    for (std::uint64_t seed = 1; seed <= 6; ++seed)
      for (const auto& [mm, deg] : {std::pair<double, double>{0.3, 0.03}, {1.0, 0.1}}) {
        SyntheticScene scene = MistakeScene(setup, seed, seed % 2 ? 14 : 30, mm, deg, seed % 3 ? 4 : 2,
                                     seed % 2 ? "small" : "medium", seed > 4 ? 6 : 7);
        if (seed > 4)  // 6×4 inner corners: two views read 180 degrees round
          for (size_t i = 0; i < scene.dataset.observations.size() && i < 14; i += 7)
            for (int& id : scene.dataset.observations[i].ids) id = 23 - id;
        const internal::SetupVerdict verdict = Judge(scene.dataset);
        INFO(SetupName(setup) << " seed " << seed << " robot " << mm << " mm: as given "
                              << verdict.given_px << " px, best repair '" << verdict.best << "' "
                              << verdict.best_px << " px");
        CHECK(verdict.mistake.empty());
        worst_ratio = std::max(worst_ratio, verdict.given_px / verdict.best_px);
        ++scenes;
      }
  INFO("worst as-given / best-repair ratio " << worst_ratio);
  CHECK(scenes == 24);
  CHECK(worst_ratio < 1.0);
}

TEST_CASE("Correct cells calibrate with default options", "[calibration][setup]") {
  for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    const SyntheticScene scene = MistakeScene(setup, 21, 16, 0.3, 0.03);
    INFO(SetupName(setup));
    CHECK_NOTHROW(Calibrate(scene.dataset, CalibrationOptions()));
  }
}

// A small or medium cell of 1-3 cameras whose given intrinsics leave out
// the lens distortion the images have (as the industrial_calibration ChArUco
// set gives its camera): the chain's residuals are pixels on correct records.
SyntheticScene WithoutDistortion(std::uint64_t seed) {
  SyntheticScene scene = MistakeScene(seed % 2 ? Setup::kEyeToHand : Setup::kEyeInHand, seed, 16,
                               seed % 3 ? 0.1 : 0.5, seed % 3 ? 0.01 : 0.05, 1 + seed % 3,
                               seed % 4 ? "small" : "medium");
  for (Camera& camera : scene.dataset.cameras) {
    std::string why;
    camera = *Camera::Make(camera.name, camera.width, camera.height, camera.fx(), camera.fy(),
                           camera.cx(), camera.cy(), {}, &why);
  }
  return scene;
}

TEST_CASE("A target declared at the wrong size is named where the lens model does not fit the images",
          "[calibration][setup]") {
  // The closed forms leave pixels of their own there; the chains refined
  // from them tell. Squares of 40 mm declared 36.4 and 44 mm. Measured: 16 of
  // the 20 named (the 4 others a medium cell's, whose closed forms or
  // refined chains leave 3-4 px either way); no correct one named.
  int named = 0;
  for (std::uint64_t seed = 21; seed <= 30; ++seed) {
    SyntheticScene scene = WithoutDistortion(seed);
    INFO("seed " << seed);
    CHECK(Judge(scene.dataset).mistake.empty());
    for (double declared : {0.0364, 0.044}) {
      scene.dataset.target = std::make_shared<const CheckerboardTarget>(7, 4, declared);
      const internal::SetupVerdict verdict = Judge(scene.dataset);
      if (verdict.mistake.empty()) continue;
      ++named;
      CHECK_THAT(verdict.mistake, Contains("the size declared"));
      const double looks_mm = std::stod(verdict.mistake.substr(verdict.mistake.find("mm, looks ") + 10));
      CHECK(std::abs(looks_mm - 40.0) < 1.0);
    }
  }
  CHECK(named >= 15);
}

TEST_CASE("A lens model the images do not follow is not taken for a robot error beyond any robot's",
          "[calibration][setup]") {
  // One camera without its distortion: the robot's error the views suggest
  // is beyond any real robot's (11-17 mm, 0.5-0.8 deg), but the exact poses
  // predict held-out views better, so it is not the robot's: exit 0 with the
  // exact robot and the misfit named: the residuals, or the intrinsics the
  // images suggest. With fewer poses than the model is otherwise chosen by
  // (10), held-out poses still decide before the data are refused.
  for (const auto& [seed, poses] :
       {std::pair<std::uint64_t, int>{21, 16}, {23, 16}, {25, 16}, {21, 10}, {23, 10}, {25, 10}}) {
    SyntheticScene scene = MistakeScene(Setup::kEyeToHand, seed, poses, 0.1, 0.01, 1, "small");
    const Camera truth = scene.dataset.cameras[0];
    std::string why;
    scene.dataset.cameras[0] = *Camera::Make(truth.name, truth.width, truth.height, truth.fx(),
                                             truth.fy(), truth.cx(), truth.cy(), {}, &why);
    INFO("seed " << seed << ", " << poses << " poses");
    CalibrationResult result;
    REQUIRE_NOTHROW(result = Calibrate(scene.dataset, CalibrationOptions()));
    REQUIRE(result.solver.model);
    CHECK(result.solver.model->chosen == "exact robot");
    CHECK(result.solver.robot_sigma_mm == 0);
    bool beyond = false;
    for (const ModelCandidate& candidate : result.solver.model->candidates)
      beyond = beyond || candidate.robot_sigma_mm > 5.0 || candidate.robot_sigma_deg > 0.5;
    CHECK(beyond);
    bool misfit_named = false;
    for (const Warning& w : result.warnings)
      misfit_named = misfit_named || w.kind == WarningKind::kLargeResiduals ||
                     w.kind == WarningKind::kIntrinsicsOff;
    CHECK(misfit_named);
  }
}
