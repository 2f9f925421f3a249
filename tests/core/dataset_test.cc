// SPDX-License-Identifier: GPL-2.0-or-later
// The dataset's small lookups (core/src/dataset.cc) and a target's point
// lookup (Target::FindPoint) on their own: setup names both ways, camera and
// pose indices, and ids that are not 0..n-1 in order.
#include "handeye/core/dataset.h"

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "handeye/core/target.h"
#include "handeye/core/target_spec.h"

using namespace handeye;

namespace {

/// A target whose point ids are sparse and out of order, as a plugin's may be.
class SparseTarget : public Target {
 public:
  SparseTarget() {
    spec_.type = "sparse";
    for (int id : {7, 3, 12, 0}) points_.push_back({id, Eigen::Vector3d(0.01 * id, 0.0, 0.0)});
  }
  std::string Type() const override { return "sparse"; }
  const TargetSpec& Spec() const override { return spec_; }
  const std::vector<TargetPoint>& Points() const override { return points_; }
  Eigen::AlignedBox2d Extent() const override {
    return Eigen::AlignedBox2d(Eigen::Vector2d(0, 0), Eigen::Vector2d(0.2, 0.01));
  }
  double Albedo(double, double) const override { return 1.0; }

 private:
  TargetSpec spec_;
  std::vector<TargetPoint> points_;
};

}  // namespace

TEST_CASE("setup names read back to their setup, and nothing else is a setup", "[dataset]") {
  for (const Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    const auto back = ParseSetup(SetupName(setup));
    REQUIRE(back);
    CHECK(*back == setup);
  }
  CHECK(std::string(SetupName(Setup::kEyeToHand)) == "eye_to_hand");
  CHECK(std::string(SetupName(Setup::kEyeInHand)) == "eye_in_hand");
  for (const std::string other : {"eye-to-hand", "EYE_TO_HAND", "eye_in_hand ", "", "eye"})
    CHECK_FALSE(ParseSetup(other));
}

TEST_CASE("a dataset finds its cameras and poses by name, -1 for none", "[dataset]") {
  Dataset dataset;
  for (const std::string name : {"left", "right", "top"}) {
    Camera camera;
    camera.name = name;
    dataset.cameras.push_back(camera);
  }
  for (const std::string id : {"0001", "0002", "0010"}) {
    RobotPose pose;
    pose.id = id;
    dataset.poses.push_back(pose);
  }
  CHECK(dataset.CameraIndex("left") == 0);
  CHECK(dataset.CameraIndex("top") == 2);
  CHECK(dataset.CameraIndex("Top") == -1);  // names are exact
  CHECK(dataset.CameraIndex("") == -1);
  CHECK(dataset.PoseIndex("0010") == 2);
  CHECK(dataset.PoseIndex("10") == -1);
  CHECK(Dataset{}.CameraIndex("left") == -1);
  CHECK(Dataset{}.PoseIndex("0001") == -1);
}

TEST_CASE("a target's point is found by id however its ids are laid out", "[dataset]") {
  const SparseTarget target;
  for (int id : {7, 3, 12, 0}) {
    const TargetPoint* p = target.FindPoint(id);
    REQUIRE(p != nullptr);
    CHECK(p->id == id);
    CHECK(p->p_target.x() == Approx(0.01 * id));
  }
  // Index 3 holds id 0, not id 3: the lookup does not trust the position.
  CHECK(target.FindPoint(3)->p_target.x() == Approx(0.03));
  for (int id : {1, 2, 4, 13, -1}) CHECK(target.FindPoint(id) == nullptr);
}
