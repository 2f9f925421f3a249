// SPDX-License-Identifier: GPL-2.0-or-later
// A solution's camera against a closed form (core/src/closed_form_comparison.cc).
// clang-format off
// Before Catch, so that CHECK is Catch's, not glog's (which Ceres' headers define).
#include "diagnostics_internal.h"
// clang-format on

#include <catch2/catch.hpp>

#include "closed_form.h"
#include "problem.h"
#include "support/problem_cell.h"

using namespace handeye;

TEST_CASE("a camera of many views is compared with the closed form on its 150 of most diverse turn",
          "[diagnostics][closed_form]") {
  // 2 cameras, 500 poses: OpenCV's closed forms pair every two views, which
  // took seconds a camera on all of them.
  const test::ProblemCell cell(test::SmallCell(Setup::kEyeToHand, 2, 500, 3), 0.3);
  const internal::Problem& all = cell.problem;
  const internal::Problem diverse = internal::WithDiverseViews(all, 150);
  for (int k = 0; k < 2; ++k) {
    INFO("camera " << k << ", " << all.camera_views[k].size() << " views");
    REQUIRE(all.camera_views[k].size() > 150);
    // A camera pose a few mm and a tenth of a degree off the truth.
    Eigen::Isometry3d T_cam_mount = cell.TrueCamMount(k);
    T_cam_mount.translation() += Eigen::Vector3d(0.003, -0.002, 0.001);
    T_cam_mount.linear() = T_cam_mount.linear() *
                           Eigen::AngleAxisd(0.002, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const auto compared = internal::CompareWithClosedForm(all, k, T_cam_mount,
                                                          cell.TrueHolderTarget(), Method::kPark);
    const auto on_diverse = internal::CompareWithClosedForm(diverse, k, T_cam_mount,
                                                            cell.TrueHolderTarget(), Method::kPark);
    REQUIRE(compared.available);
    REQUIRE(on_diverse.available);
    CHECK(compared.translation_mm == Approx(on_diverse.translation_mm).epsilon(1e-12));
    CHECK(compared.rotation_deg == Approx(on_diverse.rotation_deg).epsilon(1e-12));
    CHECK(compared.displacement_px == Approx(on_diverse.displacement_px).epsilon(1e-12));
    // And it still sees how far the camera is from the truth.
    const double off_mm = test::PositionMm(T_cam_mount.inverse(), cell.TrueCamMount(k).inverse());
    CHECK(compared.translation_mm == Approx(off_mm).margin(0.5));
  }
}

TEST_CASE("a camera of few views is compared with the closed form on all of them",
          "[diagnostics][closed_form]") {
  const test::ProblemCell cell(test::SmallCell(Setup::kEyeToHand, 2, 40, 4), 0.3);
  internal::Problem fewer = cell.problem;
  for (auto& ids : fewer.camera_views) ids.pop_back();
  for (int k = 0; k < 2; ++k) {
    const Eigen::Isometry3d T_cam_mount = cell.TrueCamMount(k);
    const auto all = internal::CompareWithClosedForm(cell.problem, k, T_cam_mount,
                                                     cell.TrueHolderTarget(), Method::kPark);
    const auto one_less = internal::CompareWithClosedForm(fewer, k, T_cam_mount,
                                                          cell.TrueHolderTarget(), Method::kPark);
    REQUIRE(all.available);
    CHECK(all.displacement_px != one_less.displacement_px);
  }
}
