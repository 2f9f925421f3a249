// SPDX-License-Identifier: GPL-2.0-or-later
// The σ in the result is honest: over small, medium and large cells, with
// detection noise of 0.1 and 0.3 px and robot pose error of 0 to 0.3 mm, the
// cameras whose true error lies within 2σ are 85–98 % (bench_uncertainty
// prints the table over more seeds).
#include <catch2/catch.hpp>
#include <cstdio>

#include "handeye/core/synthetic.h"

using namespace handeye;

TEST_CASE("The result's sigma covers the true error as a sigma should", "[uncertainty]") {
  int cameras = 0, position = 0, rotation = 0;
  for (const char* cell : {"small", "medium", "large"})
    for (const auto& [robot_mm, robot_deg] : {std::pair{0.0, 0.0}, {0.1, 0.01}, {0.3, 0.03}})
      for (double noise_px : {0.1, 0.3}) {
        SceneOptions options;
        options.cell = cell;
        options.num_cameras = 4;
        options.num_poses = 20;
        options.pose_noise_mm = robot_mm;
        options.pose_noise_deg = robot_deg;
        const SigmaCoverage c = MeasureSigmaCoverage(options, noise_px, 3, 1001);
        for (const auto& failure : c.failures) INFO(failure);
        CHECK(c.failures.empty());
        cameras += c.cameras;
        position += c.position_within_2sigma;
        rotation += c.rotation_within_2sigma;
      }
  const double position_coverage = double(position) / cameras, rotation_coverage = double(rotation) / cameras;
  std::printf("sigma coverage over %d cameras: position %.1f %%, rotation %.1f %%\n", cameras,
              100 * position_coverage, 100 * rotation_coverage);
  REQUIRE(cameras == 216);
  CHECK(position_coverage >= 0.85);
  CHECK(position_coverage <= 0.98);
  CHECK(rotation_coverage >= 0.85);
  CHECK(rotation_coverage <= 0.98);
}
