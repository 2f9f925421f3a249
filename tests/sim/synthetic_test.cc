// SPDX-License-Identifier: GPL-2.0-or-later
#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "handeye/core/checkerboard.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "handeye/sim/synthetic.h"

using namespace handeye;

namespace {

constexpr double kDeg = M_PI / 180.0;

std::shared_ptr<const Target> DefaultBoard() {
  return std::make_shared<const CheckerboardTarget>(7, 4, 0.04);
}

SceneOptions Options(const std::string& cell, Setup setup, std::uint64_t seed = 1) {
  SceneOptions options;
  options.cell = cell;
  options.setup = setup;
  options.seed = seed;
  return options;
}

bool SameTransform(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return a.matrix() == b.matrix();
}

/// Number of poses in which at least two cameras see the target.
int SharedPoses(const SyntheticScene& scene) {
  int shared = 0;
  for (const auto& pose : scene.truth.poses) shared += pose.points_px.size() >= 2 ? 1 : 0;
  return shared;
}

std::map<std::string, int> ViewsPerCamera(const SyntheticScene& scene) {
  std::map<std::string, int> views;
  for (const auto& camera : scene.dataset.cameras) views[camera.name] = 0;
  for (const auto& pose : scene.truth.poses)
    for (const auto& [name, obs] : pose.points_px) ++views[name];
  return views;
}

}  // namespace

TEST_CASE("SceneOptions::Check accepts the defaults and names what is wrong", "[synthetic]") {
  std::string why;
  CHECK(SceneOptions().Check(&why));
  SceneOptions options;
  options.cell = "huge";
  CHECK_FALSE(options.Check(&why));
  CHECK_THAT(why, Catch::Contains("huge") && Catch::Contains("metric-medium"));
  options = SceneOptions();
  options.num_cameras = 0;
  CHECK_FALSE(options.Check(&why));
  CHECK_THAT(why, Catch::Contains("cameras"));
  options = SceneOptions();
  options.num_poses = 0;
  CHECK_FALSE(options.Check(&why));
  CHECK_THAT(why, Catch::Contains("poses"));
  options = SceneOptions();
  options.width = 640;
  CHECK_FALSE(options.Check(&why));
  CHECK_THAT(why, Catch::Contains("width and height"));
  options = SceneOptions();
  options.pose_noise_mm = -1;
  CHECK_FALSE(options.Check(&why));
  CHECK_THAT(why, Catch::Contains("translation noise"));
  options = SceneOptions();
  options.pose_noise_deg = std::nan("");
  CHECK_FALSE(options.Check(&why));
  CHECK_THAT(why, Catch::Contains("rotation noise"));
  options = SceneOptions();
  options.border_margin_px = -1;
  CHECK_FALSE(options.Check(&why));
  CHECK_THAT(why, Catch::Contains("border margin"));
}

TEST_CASE("A seed gives the same scene, another seed a different one", "[synthetic]") {
  for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    const SyntheticScene a = MakeScene(Options("medium", setup, 7), DefaultBoard());
    const SyntheticScene b = MakeScene(Options("medium", setup, 7), DefaultBoard());
    const SyntheticScene c = MakeScene(Options("medium", setup, 8), DefaultBoard());
    REQUIRE(a.dataset.cameras.size() == 4);
    REQUIRE(a.dataset.poses.size() == 20);
    CHECK(a.truth.has_T_target);
    REQUIRE(b.truth.poses.size() == a.truth.poses.size());
    CHECK(SameTransform(a.truth.T_target, b.truth.T_target));
    CHECK_FALSE(SameTransform(a.truth.T_target, c.truth.T_target));
    for (size_t k = 0; k < a.dataset.cameras.size(); ++k) {
      const std::string& name = a.dataset.cameras[k].name;
      CHECK(a.dataset.cameras[k].params == b.dataset.cameras[k].params);
      CHECK(SameTransform(a.truth.T_cam.at(name), b.truth.T_cam.at(name)));
      CHECK_FALSE(SameTransform(a.truth.T_cam.at(name), c.truth.T_cam.at(name)));
    }
    for (size_t j = 0; j < a.truth.poses.size(); ++j) {
      CHECK(a.dataset.poses[j].id == b.dataset.poses[j].id);
      CHECK(SameTransform(a.dataset.poses[j].T_base_ee, b.dataset.poses[j].T_base_ee));
      CHECK(SameTransform(a.truth.poses[j].T_base_ee_true, b.truth.poses[j].T_base_ee_true));
      REQUIRE(a.truth.poses[j].points_px.size() == b.truth.poses[j].points_px.size());
      for (const auto& [name, obs] : a.truth.poses[j].points_px) {
        const Observation& other = b.truth.poses[j].points_px.at(name);
        CHECK(obs.ids == other.ids);
        CHECK(obs.points_px == other.points_px);
      }
    }
  }
}

TEST_CASE("Every camera has views and neighbours share some, in every cell", "[synthetic]") {
  for (const char* cell : {"small", "medium", "large", "metric-medium"})
    for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand})
      for (std::uint64_t seed : {1, 2, 3}) {
        const SyntheticScene scene = MakeScene(Options(cell, setup, seed), DefaultBoard());
        INFO(cell << " " << SetupName(setup) << " seed " << seed);
        REQUIRE(scene.truth.poses.size() == 20);
        for (const auto& [name, views] : ViewsPerCamera(scene)) {
          INFO(name);
          CHECK(views >= 3);
        }
        CHECK(SharedPoses(scene) >= 4);
        for (const auto& pose : scene.truth.poses) CHECK_FALSE(pose.points_px.empty());
      }
}

TEST_CASE("True pixels are the projections of the true poses, views are whole boards", "[synthetic]") {
  for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    const SyntheticScene scene = MakeScene(Options("small", setup, 3), DefaultBoard());
    const Target& target = *scene.dataset.target;
    int views = 0;
    for (size_t j = 0; j < scene.truth.poses.size(); ++j) {
      const auto& pose = scene.truth.poses[j];
      CHECK(pose.id == scene.dataset.poses[j].id);
      for (const auto& [name, obs] : pose.points_px) {
        const int k = scene.dataset.CameraIndex(name);
        REQUIRE(k >= 0);
        const Camera& camera = scene.dataset.cameras[k];
        CHECK(obs.camera == name);
        CHECK(obs.pose_id == pose.id);
        // A checkerboard view counts only when every corner is seen.
        REQUIRE(obs.ids.size() == target.Points().size());
        const Eigen::Isometry3d T_cam_target = TrueCameraFromTarget(scene, k, static_cast<int>(j));
        for (size_t i = 0; i < obs.ids.size(); ++i) {
          const auto uv = camera.Project(T_cam_target * target.FindPoint(obs.ids[i])->p_target);
          REQUIRE(uv);
          CHECK((*uv - obs.points_px[i]).norm() < 1e-9);
          CHECK(camera.InImage(obs.points_px[i], 4.0));
        }
        ++views;
      }
    }
    CHECK(views > 20);
  }
}

TEST_CASE("Only the printed face is seen: never from behind, never edge-on", "[synthetic]") {
  int turned_away = 0;
  for (std::uint64_t seed : {1, 2}) {
    SceneOptions options = Options("medium", Setup::kEyeToHand, seed);
    options.num_poses = 40;
    const SyntheticScene scene = MakeScene(options, DefaultBoard());
    for (size_t j = 0; j < scene.truth.poses.size(); ++j)
      for (size_t k = 0; k < scene.dataset.cameras.size(); ++k) {
        const Eigen::Isometry3d T_cam_target = TrueCameraFromTarget(scene, int(k), int(j));
        // Printed face normal is the target's -z; the camera looks at it when
        // that normal points back towards the camera centre.
        const Eigen::Vector3d centre_cam = T_cam_target * Eigen::Vector3d(0.12, 0.06, 0.0);
        const double facing = (-T_cam_target.linear().col(2)).dot(-centre_cam.normalized());
        const bool seen = scene.truth.poses[j].points_px.count(scene.dataset.cameras[k].name) > 0;
        if (facing <= 0) {
          ++turned_away;
          CHECK_FALSE(seen);
        }
        // Views that count are at most 70° off the face normal at every corner;
        // the centre is a fair proxy with a degree to spare.
        if (seen) CHECK(facing > std::cos(71.0 * kDeg));
      }
  }
  // The scene does contain cameras that see the board's back, so the check above bites.
  CHECK(turned_away > 20);
}

TEST_CASE("Projected observations carry Gaussian noise of the requested sigma", "[synthetic]") {
  SyntheticScene scene = MakeScene(Options("medium", Setup::kEyeToHand, 5), DefaultBoard());
  std::mt19937_64 rng(11);
  AddProjectedObservations(&scene, 0.0, &rng);
  std::size_t views = 0;
  for (const auto& pose : scene.truth.poses) views += pose.points_px.size();
  REQUIRE(scene.dataset.observations.size() == views);
  for (const Observation& obs : scene.dataset.observations) {
    const int j = scene.dataset.PoseIndex(obs.pose_id);
    REQUIRE(j >= 0);
    const Observation& truth = scene.truth.poses[j].points_px.at(obs.camera);
    CHECK(obs.ids == truth.ids);
    CHECK(obs.points_px == truth.points_px);
  }

  const double sigma = 0.5;
  AddProjectedObservations(&scene, sigma, &rng);
  REQUIRE(scene.dataset.observations.size() == views);  // replaced, not appended
  double sum = 0, sum_sq = 0;
  std::size_t n = 0;
  for (const Observation& obs : scene.dataset.observations) {
    const int j = scene.dataset.PoseIndex(obs.pose_id);
    const Observation& truth = scene.truth.poses[j].points_px.at(obs.camera);
    REQUIRE(obs.ids == truth.ids);
    for (size_t i = 0; i < obs.points_px.size(); ++i)
      for (int axis = 0; axis < 2; ++axis) {
        const double e = obs.points_px[i][axis] - truth.points_px[i][axis];
        sum += e;
        sum_sq += e * e;
        ++n;
      }
  }
  REQUIRE(n > 1000);
  const double mean = sum / n;
  const double std_dev = std::sqrt(sum_sq / n - mean * mean);
  INFO("n " << n << " mean " << mean << " std " << std_dev);
  // Bounds are 5 standard errors of the estimates for this n.
  CHECK(std::abs(mean) < 5 * sigma / std::sqrt(double(n)));
  CHECK(std::abs(std_dev - sigma) < 5 * sigma / std::sqrt(2.0 * n));
}

TEST_CASE("eye_to_hand: cameras around the robot, target on the flange", "[synthetic]") {
  for (const char* cell : {"small", "medium", "large"}) {
    const SyntheticScene scene = MakeScene(Options(cell, Setup::kEyeToHand, 2), DefaultBoard());
    INFO(cell);
    CHECK(scene.truth.setup == Setup::kEyeToHand);
    CHECK(scene.dataset.setup == Setup::kEyeToHand);
    // Sheet centre 5–15 cm in front of the flange (and up to ≈3 cm off axis).
    const Eigen::Vector3d centre_ee = scene.truth.T_target * Eigen::Vector3d(0.12, 0.06, 0.0);
    CHECK(centre_ee.norm() > 0.05);
    CHECK(centre_ee.norm() < 0.16);
    for (const Camera& camera : scene.dataset.cameras) {
      const Eigen::Vector3d p = scene.truth.T_cam.at(camera.name).translation();
      CHECK(p.z() >= 1.8);
      CHECK(p.z() <= 2.6);
      CHECK(camera.width == 1920);
      CHECK(camera.height == 1080);
      CHECK(camera.num_distortion == 5);
      CHECK(camera.params[4] >= -0.15);
      CHECK(camera.params[4] <= 0.02);
      // Invertible over the whole image.
      for (const Eigen::Vector2d& corner :
           {Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(1919.5, 1079.5)})
        CHECK(camera.Undistort(corner).has_value());
    }
    // Target centre in the stated workspace, and camera distances near the preset's.
    double distance_sum = 0;
    int views = 0;
    for (size_t j = 0; j < scene.truth.poses.size(); ++j) {
      const Eigen::Vector3d c =
          scene.truth.poses[j].T_base_ee_true * (scene.truth.T_target * Eigen::Vector3d(0.12, 0.06, 0));
      CHECK(std::hypot(c.x(), c.y()) >= 0.4 - 1e-9);
      CHECK(std::hypot(c.x(), c.y()) <= 0.9 + 1e-9);
      CHECK(c.z() >= 0.7 - 1e-9);
      CHECK(c.z() <= 1.5 + 1e-9);
      for (const auto& [name, obs] : scene.truth.poses[j].points_px) {
        distance_sum += (scene.truth.T_cam.at(name).translation() - c).norm();
        ++views;
      }
    }
    const double nominal = std::string(cell) == "small" ? 1.5 : std::string(cell) == "medium" ? 2.5 : 4.0;
    CHECK(distance_sum / views == Approx(nominal).epsilon(0.15));
  }
}

TEST_CASE("eye_in_hand: a rig on the flange, the target fixed in the cell", "[synthetic]") {
  for (const char* cell : {"small", "large"}) {
    const SyntheticScene scene = MakeScene(Options(cell, Setup::kEyeInHand, 4), DefaultBoard());
    INFO(cell);
    CHECK(scene.truth.setup == Setup::kEyeInHand);
    for (const Camera& camera : scene.dataset.cameras) {
      const Eigen::Isometry3d& T_ee_cam = scene.truth.T_cam.at(camera.name);
      CHECK(T_ee_cam.translation().norm() < 0.15);
      // Looks forward along the tool axis, in slightly different directions.
      const double off_axis = std::acos(T_ee_cam.linear().col(2).z());
      CHECK(off_axis > 2.9 * kDeg);
      CHECK(off_axis < 8.1 * kDeg);
    }
    const double nominal = std::string(cell) == "small" ? 1.5 : 4.0;
    double distance_sum = 0;
    int views = 0;
    for (size_t j = 0; j < scene.truth.poses.size(); ++j)
      for (const auto& [name, obs] : scene.truth.poses[j].points_px) {
        const int k = scene.dataset.CameraIndex(name);
        distance_sum += (TrueCameraFromTarget(scene, k, int(j)) * Eigen::Vector3d(0.12, 0.06, 0)).norm();
        ++views;
      }
    CHECK(distance_sum / views == Approx(nominal).epsilon(0.15));
  }
}

TEST_CASE("metric-medium reproduces METRIC's synthetic medium cell", "[synthetic]") {
  SceneOptions options = Options("metric-medium", Setup::kEyeToHand, 9);
  const SyntheticScene scene =
      MakeScene(options, std::make_shared<const CheckerboardTarget>(4, 3, 0.05));
  REQUIRE(scene.dataset.cameras.size() == 4);
  for (const Camera& camera : scene.dataset.cameras) {
    CHECK(camera.width == 1920);
    CHECK(camera.height == 1080);
    CHECK(camera.fx() == 1371.02);
    CHECK(camera.fy() == 1371.02);
    CHECK(camera.cx() == 960.5);
    CHECK(camera.cy() == 540.5);
    CHECK_FALSE(camera.HasDistortion());
    const Eigen::Vector3d p = scene.truth.T_cam.at(camera.name).translation();
    CHECK(std::hypot(p.x(), p.y()) == Approx(2.3).margin(0.05));
    CHECK(p.z() == Approx(1.15).margin(0.03));
  }
}

TEST_CASE("Explicit options override the preset: image size, no distortion", "[synthetic]") {
  SceneOptions options = Options("large", Setup::kEyeToHand, 3);
  options.width = 960;
  options.height = 540;
  options.distortion = false;
  const SyntheticScene scene = MakeScene(options, DefaultBoard());
  for (const Camera& camera : scene.dataset.cameras) {
    CHECK(camera.width == 960);
    CHECK(camera.height == 540);
    CHECK_FALSE(camera.HasDistortion());
    // The field of view is the preset's: fx scales with the width.
    CHECK(camera.fx() == Approx(0.95 * 960).epsilon(0.031));
  }
  SceneOptions metric = Options("metric-medium", Setup::kEyeToHand, 3);
  metric.width = 960;
  metric.height = 540;
  const SyntheticScene half = MakeScene(metric, DefaultBoard());
  CHECK(half.dataset.cameras[0].fx() == Approx(1371.02 / 2));
  CHECK(half.dataset.cameras[0].cx() == Approx(480.5));
}

TEST_CASE("Robot pose noise changes only the reported poses", "[synthetic]") {
  SceneOptions options = Options("medium", Setup::kEyeToHand, 6);
  options.num_cameras = 2;
  options.num_poses = 240;
  const SyntheticScene clean = MakeScene(options, DefaultBoard());
  options.pose_noise_mm = 0.8;
  options.pose_noise_deg = 0.1;
  const SyntheticScene noisy = MakeScene(options, DefaultBoard());

  CHECK(SameTransform(clean.truth.T_target, noisy.truth.T_target));
  REQUIRE(noisy.truth.poses.size() == clean.truth.poses.size());
  double sum_sq_mm = 0, sum_sq_deg = 0;
  for (size_t j = 0; j < clean.truth.poses.size(); ++j) {
    CHECK(SameTransform(clean.dataset.poses[j].T_base_ee, clean.truth.poses[j].T_base_ee_true));
    CHECK(SameTransform(clean.truth.poses[j].T_base_ee_true, noisy.truth.poses[j].T_base_ee_true));
    CHECK(clean.truth.poses[j].points_px.size() == noisy.truth.poses[j].points_px.size());
    const Eigen::Isometry3d& reported = noisy.dataset.poses[j].T_base_ee;
    const Eigen::Isometry3d& truth = noisy.truth.poses[j].T_base_ee_true;
    sum_sq_mm += (1000 * (reported.translation() - truth.translation())).squaredNorm();
    const double angle_deg = RotationDistance(reported.linear(), truth.linear()) / kDeg;
    sum_sq_deg += angle_deg * angle_deg;
  }
  const double n = clean.truth.poses.size();
  const double rms_mm_per_axis = std::sqrt(sum_sq_mm / (3 * n));
  const double rms_deg = std::sqrt(sum_sq_deg / n);
  INFO("rms " << rms_mm_per_axis << " mm per axis, " << rms_deg << " deg");
  // 5 standard errors of an RMS estimated from 3n and n samples.
  CHECK(std::abs(rms_mm_per_axis - 0.8) < 5 * 0.8 / std::sqrt(6 * n));
  CHECK(std::abs(rms_deg - 0.1) < 5 * 0.1 / std::sqrt(2 * n));
}

TEST_CASE("Robot motions rotate about axes that span 3-D", "[synthetic]") {
  for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand})
    for (const char* cell : {"small", "large"}) {
      INFO(SetupName(setup) << " " << cell);
      const SyntheticScene scene = MakeScene(Options(cell, setup, 1), DefaultBoard());
      // Scatter of the unit axes of the motions between consecutive poses:
      // parallel axes (unusable for hand-eye) give one large eigenvalue only.
      Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
      int motions = 0;
      for (size_t j = 0; j + 1 < scene.truth.poses.size(); ++j) {
        const Eigen::Isometry3d A =
            scene.truth.poses[j].T_base_ee_true.inverse() * scene.truth.poses[j + 1].T_base_ee_true;
        const Eigen::Vector3d rotvec = RotationVectorFromMatrix(A.linear());
        if (rotvec.norm() < 10 * kDeg) continue;
        const Eigen::Vector3d axis = rotvec.normalized();
        scatter += axis * axis.transpose();
        ++motions;
      }
      REQUIRE(motions >= 10);
      const Eigen::Vector3d eig = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter / motions).eigenvalues();
      INFO("eigenvalues " << eig.transpose());
      CHECK(eig(0) > 0.05);
    }
}

TEST_CASE("A target that fits in no view is reported as bad input", "[synthetic]") {
  SceneOptions options = Options("small", Setup::kEyeToHand, 1);
  options.num_poses = 1;
  const auto huge = std::make_shared<const CheckerboardTarget>(7, 4, 1.0);
  CHECK_THROWS_AS(MakeScene(options, huge), InputError);
  CHECK_THROWS_WITH(MakeScene(options, huge), Catch::Contains("sees the whole target"));
}
