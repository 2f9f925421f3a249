// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/repeated_images.h"

#include <catch2/catch.hpp>

#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;

Dataset TwoCameras(const std::vector<std::map<std::string, std::string>>& images) {
  Dataset d;
  d.cameras.resize(2);
  d.cameras[0].name = "cam0";
  d.cameras[1].name = "cam1";
  for (size_t j = 0; j < images.size(); ++j) {
    RobotPose pose;
    pose.id = "p" + std::to_string(j);
    pose.images = images[j];
    d.poses.push_back(pose);
  }
  return d;
}

}  // namespace

TEST_CASE("Images listed for several poses are named: one path, or the same bytes",
          "[io][repeated]") {
  const std::string dir = test::TempDir("repeated_images");
  // Files of one size: a copy (same bytes), and one differing in its last byte
  // only (beyond the first 64 KiB read first).
  std::string bytes(100000, 'a');
  test::WriteText(dir + "/a.png", bytes);
  test::WriteText(dir + "/copy_of_a.png", bytes);
  bytes.back() = 'b';
  test::WriteText(dir + "/almost_a.png", bytes);
  test::WriteText(dir + "/other.png", "another picture");
  const Dataset d = TwoCameras({{{"cam0", dir + "/a.png"}, {"cam1", dir + "/a.png"}},
                                {{"cam0", dir + "/copy_of_a.png"}, {"cam1", dir + "/other.png"}},
                                {{"cam0", dir + "/almost_a.png"}, {"cam1", dir + "/./a.png"}},
                                {{"cam0", dir + "/missing.png"}}});
  const std::vector<std::string> warnings = WarningTexts(RepeatedImageWarnings(d));
  REQUIRE(warnings.size() == 2);
  CHECK(RepeatedImageWarnings(d)[1].camera == "cam1");
  CHECK(RepeatedImageWarnings(d)[1].kind == WarningKind::kRepeatedImages);
  // cam0: p0 and p1 are byte for byte the same; almost_a is not, missing is skipped.
  CHECK_THAT(warnings[0],
             Contains("camera 'cam0': the images of poses 'p0', 'p1' are byte for byte the same"));
  CHECK_THAT(warnings[0], Contains("copy_of_a.png"));
  CHECK_THAT(warnings[0], !Contains("almost_a.png"));
  // cam1: one file under two poses (the path written two ways).
  CHECK_THAT(warnings[1], Contains("camera 'cam1': the images of poses 'p0', 'p2' are one file"));
  CHECK_THAT(warnings[1], Contains("one picture under 2 robot poses"));

  CHECK(RepeatedImageWarnings(
            TwoCameras({{{"cam0", dir + "/a.png"}}, {{"cam0", dir + "/other.png"}}}))
            .empty());
}

}  // namespace handeye
