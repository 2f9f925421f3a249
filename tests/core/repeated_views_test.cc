// SPDX-License-Identifier: GPL-2.0-or-later
// LeaveOutRepeatedViews (core/src/repeated_views.cc) on its own: which views
// it leaves out, what each says, when it stops the calibration, and what it
// leaves alone (other cameras, points that differ in one bit, views too
// small to tell).
// clang-format off
// Before Catch, so that CHECK is Catch's, not glog's (which Ceres' headers define).
#include "problem.h"
#include "setup_mistakes.h"
// clang-format on
#include <catch2/catch.hpp>
#include <string>

#include "handeye/core/error.h"
#include "support/problem_cell.h"

using namespace handeye;
using Catch::Matchers::Contains;

namespace {

/// 2 cameras, 12 poses of a projected small cell; every view with its points.
SyntheticScene RepeatedViewsScene() { return test::ProjectedScene("small", 2, 12, 21, 0.1); }

/// The observations of `camera`, in the dataset's order.
std::vector<Observation*> ViewsOf(Dataset* dataset, const std::string& camera) {
  std::vector<Observation*> out;
  for (Observation& obs : dataset->observations)
    if (obs.camera == camera && obs.ids.size() >= 4) out.push_back(&obs);
  return out;
}

/// Copies the points of `from` into `to` (the same image under two poses).
void Repeat(const Observation& from, Observation* to) {
  to->ids = from.ids;
  to->points_px = from.points_px;
}

}  // namespace

TEST_CASE("repeated views: both copies left out, each naming the other pose and the file",
          "[setup][repeated]") {
  SyntheticScene scene = RepeatedViewsScene();
  Dataset& dataset = scene.dataset;
  const std::vector<Observation*> cam0 = ViewsOf(&dataset, "cam0");
  REQUIRE(cam0.size() >= 6);
  Observation* a = cam0[1];
  Observation* b = cam0[5];
  Repeat(*a, b);
  for (RobotPose& pose : dataset.poses)
    if (pose.id == a->pose_id || pose.id == b->pose_id)
      pose.images["cam0"] = "images/cam0/same.png";
  internal::Problem problem = internal::BuildProblem(dataset, CalibrationOptions{});
  const int before = test::UsedViews(problem);
  const size_t cam0_before = problem.camera_views[0].size(),
               cam1_before = problem.camera_views[1].size();
  internal::LeaveOutRepeatedViews(&problem);
  CHECK(test::UsedViews(problem) == before - 2);
  int left_out = 0;
  for (const internal::View& view : problem.views) {
    if (view.used) continue;
    ++left_out;
    const std::string other = view.observation == a ? b->pose_id : a->pose_id;
    CHECK(view.observation->camera == "cam0");
    CHECK_THAT(view.rejected_because,
               Contains("identical to those of the same camera at pose(s) '" + other + "'"));
    CHECK_THAT(view.rejected_because,
               Contains("all listing the image file 'images/cam0/same.png'"));
  }
  CHECK(left_out == 2);
  // The used views' index follows: cam0 lost two, cam1 none.
  CHECK(problem.camera_views[0].size() == cam0_before - 2);
  CHECK(problem.camera_views[1].size() == cam1_before);
  for (int v : problem.camera_views[0]) CHECK(problem.views[v].used);
}

TEST_CASE("repeated views: different files are not said to be one, other cameras are left alone",
          "[setup][repeated]") {
  SyntheticScene scene = RepeatedViewsScene();
  Dataset& dataset = scene.dataset;
  const std::vector<Observation*> cam1 = ViewsOf(&dataset, "cam1");
  REQUIRE(cam1.size() >= 6);
  Observation *a = cam1[0], *b = cam1[3], *c = cam1[5];
  Repeat(*a, b);
  Repeat(*a, c);
  internal::Problem problem = internal::BuildProblem(dataset, CalibrationOptions{});
  internal::LeaveOutRepeatedViews(&problem);
  int left_out = 0;
  for (const internal::View& view : problem.views) {
    if (view.used) continue;
    ++left_out;
    CHECK(view.observation->camera == "cam1");
    // Three copies: each names the two others, and no common file (each pose lists its own).
    CHECK(view.rejected_because.find("all listing the image file") == std::string::npos);
    for (const Observation* other : {a, b, c})
      if (other != view.observation)
        CHECK_THAT(view.rejected_because, Contains("'" + other->pose_id + "'"));
  }
  CHECK(left_out == 3);
}

TEST_CASE("repeated views: a difference in one pixel's last bit, or too few points, is no repeat",
          "[setup][repeated]") {
  SyntheticScene scene = RepeatedViewsScene();
  Dataset& dataset = scene.dataset;
  const std::vector<Observation*> cam0 = ViewsOf(&dataset, "cam0");
  REQUIRE(cam0.size() >= 4);
  Observation *a = cam0[1], *b = cam0[3];
  Repeat(*a, b);
  b->points_px.back().x() = std::nextafter(b->points_px.back().x(), 1e9);
  internal::Problem problem = internal::BuildProblem(dataset, CalibrationOptions{});
  const int before = test::UsedViews(problem);
  internal::LeaveOutRepeatedViews(&problem);
  CHECK(test::UsedViews(problem) == before);
}

TEST_CASE("repeated views: a third of a camera network's views or more stops the calibration",
          "[setup][repeated]") {
  SyntheticScene scene = RepeatedViewsScene();
  Dataset& dataset = scene.dataset;
  int views = 0;
  for (const Observation& obs : dataset.observations) views += obs.ids.size() >= 4;
  // Copy cam0's first view over its next ones until a third of all views (less one) repeat it.
  const std::vector<Observation*> cam0 = ViewsOf(&dataset, "cam0");
  Observation* first = cam0.front();
  int copies = 1;
  size_t j = 1;
  for (; j < cam0.size() && 3 * copies < views - 3; ++j) {
    Repeat(*first, cam0[j]);
    ++copies;
  }
  REQUIRE(3 * copies >= views - 3);  // cam0 has views enough to reach a third
  {
    internal::Problem problem = internal::BuildProblem(dataset, CalibrationOptions{});
    CHECK_NOTHROW(internal::LeaveOutRepeatedViews(&problem));  // just under a third
    CHECK(test::UsedViews(problem) == views - copies);
  }
  REQUIRE(j < cam0.size());
  Observation* more = cam0[j];
  Repeat(*first, more);
  internal::Problem problem = internal::BuildProblem(dataset, CalibrationOptions{});
  CHECK_THROWS_WITH(internal::LeaveOutRepeatedViews(&problem),
                    Contains(std::to_string(copies + 1) + " of " + std::to_string(views) +
                             " views repeat another view's detected points exactly") &&
                        Contains("camera 'cam0' at poses '" + first->pose_id + "'") &&
                        Contains("--accept-setup"));
}
