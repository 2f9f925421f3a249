// SPDX-License-Identifier: GPL-2.0-or-later
// The example in docs/example/ is what a user copies first: it must load,
// and mean what docs/formats.md says it means.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "handeye/io/dataset_json.h"

namespace handeye {
namespace {

const std::filesystem::path kExample =
    std::filesystem::path(HANDEYE_TEST_SOURCE_DIR "/../docs/example");

TEST_CASE("docs/example/dataset.json loads as the documentation describes it",
          "[io][dataset][docs]") {
  std::vector<Warning> warnings;
  const Dataset d = LoadDataset((kExample / "dataset.json").string(), {}, &warnings);
  CHECK(d.setup == Setup::kEyeToHand);
  REQUIRE(d.cameras.size() == 2);
  CHECK(d.cameras[0].name == "left");
  CHECK(d.cameras[0].fx() == 1250.0);
  CHECK(d.cameras[0].Distortion() == std::vector<double>{-0.11, 0.08, 0.0002, -0.0001, 0.0});
  // The right camera's intrinsics and image size come from its ROS file.
  CHECK(d.cameras[1].name == "right");
  CHECK(d.cameras[1].fx() == 1262.4);
  CHECK(d.cameras[1].width == 1280);
  CHECK(d.cameras[1].height == 1024);
  CHECK(d.cameras[1].Distortion() == std::vector<double>{-0.105, 0.072, 0.0001, 0.0003, 0.0});
  REQUIRE(d.poses.size() == 3);
  // Pose 0002: KUKA A = 90°, B = 0, C = 180° is Rz(90)·Rx(180), in millimetres.
  Eigen::Matrix3d R;
  R << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  CHECK((d.poses[1].T_base_ee.rotation() - R).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((d.poses[1].T_base_ee.translation() - Eigen::Vector3d(0.45, -0.02, 0.88)).norm() < 1e-15);
  // Pose 0003: 30° about y.
  CHECK(std::abs(Eigen::AngleAxisd(d.poses[2].T_base_ee.rotation()).angle() - M_PI / 6) < 1e-6);
  CHECK(d.poses[2].images.size() == 1);
  CHECK(d.poses[0].images.at("right") ==
        (kExample / "images/right/0001.png").lexically_normal().string());
  CHECK(warnings.empty());
}

TEST_CASE("docs/example/observations.json loads with its views", "[io][dataset][docs]") {
  const Dataset d = LoadDataset((kExample / "observations.json").string());
  CHECK(d.cameras.size() == 2);
  CHECK(d.poses.size() == 3);
  REQUIRE(d.observations.size() == 2);
  CHECK(d.observations[0].ids == std::vector<int>{0, 1, 2});
}

}  // namespace
}  // namespace handeye
