// SPDX-License-Identifier: GPL-2.0-or-later
// Inputs that declared gigabytes: a 65536 x 65536 camera whose PNG decoded
// to 9.5 GB, boards of 20000 x 20000 (12.5 GB) and 100000 x 100000
// (std::bad_alloc, exit 1). Each is now exit 2 from a small process.
#include <sys/resource.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "support/test_support.h"

using Catch::Matchers::Contains;

namespace {

// The largest resident size of any child process waited for so far, bytes.
long PeakChildBytes() {
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  return usage.ru_maxrss * 1024L;
}

// A valid small PNG whose header then says 65536 x 65536 (its CRC fixed).
void WritePngDeclaring65536(const std::string& path) {
  std::vector<std::uint8_t> png;
  REQUIRE(cv::imencode(".png", cv::Mat(8, 8, CV_8UC1, cv::Scalar(90)), png));
  for (int at : {16, 20})
    png[at] = 0, png[at + 1] = 1, png[at + 2] = 0, png[at + 3] = 0;  // IHDR width, height
  const std::uint32_t crc = handeye::test::Crc32(png.data() + 12, 17);
  for (int k = 0; k < 4; ++k) png[29 + k] = static_cast<std::uint8_t>(crc >> (24 - 8 * k));
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(png.data()), png.size());
}

}  // namespace

TEST_CASE("A camera or board declared too large exits 2 without allocating it", "[cli][limits]") {
  const std::string dir = handeye::test::TempDir("limits_cli");
  WritePngDeclaring65536(dir + "/huge.png");
  nlohmann::json dataset = {
      {"format", "handeye-dataset/1"},
      {"setup", "eye_to_hand"},
      {"target", {{"type", "checkerboard"}, {"inner_corners", {7, 4}}, {"square_size_m", 0.04}}},
      {"cameras",
       {{{"name", "cam"},
         {"image_size", {65536, 65536}},
         {"intrinsics", {{"fx", 9e4}, {"fy", 9e4}, {"cx", 32767.5}, {"cy", 32767.5}}},
         {"distortion", {{"model", "none"}}}}}},
      {"poses",
       {{{"id", "1"},
         {"T_base_ee", {{1, 0, 0, 0.4}, {0, 1, 0, 0}, {0, 0, 1, 0.9}, {0, 0, 0, 1}}},
         {"images", {{"cam", "huge.png"}}}}}}};
  handeye::test::WriteText(dir + "/d.json", dataset.dump());
  std::string out;
  CHECK(handeye::test::RunHandeye("detect " + dir + "/d.json -o " + dir + "/obs.json", &out) == 2);
  CHECK_THAT(out,
             Contains(dir + "/d.json: at /cameras/0/image_size: 65536 x 65536 = 4294967296 pixels; "
                            "expected at most 200000000 per image (raise it with --max-image-pixels or HANDEYE_MAX_IMAGE_PIXELS"));
  for (const char* board : {"20000x20000", "100000x100000"}) {
    INFO(board);
    CHECK(handeye::test::RunHandeye(
              std::string("target checkerboard --board ") + board + " -o " + dir + "/b.png",
              &out) == 2);
    CHECK_THAT(out,
               Contains("target points; expected at most 20000 (raise it with --max-target-points or HANDEYE_MAX_TARGET_POINTS"));
  }
  // Before, the first took 9.5 GB and the second 12.5 GB; a process that
  // stops at the header stays under 300 MB.
  CHECK(PeakChildBytes() < 300L * 1024 * 1024);
}

TEST_CASE("The flags --max-target-points and --max-image-pixels raise or lower the caps for any command", "[cli][limits]") {
  const std::string dir = handeye::test::TempDir("limits_cli_flags");
  std::string out;
  // A 30 x 30 board (900 points) is within the default; lowered to 500 it is not.
  CHECK(handeye::test::RunHandeye("target checkerboard --board 30x30 --square 0.002 -o " + dir + "/a.png", &out) == 0);
  CHECK(handeye::test::RunHandeye("target checkerboard --board 30x30 --square 0.002 -o " + dir + "/b.png --max-target-points 500",
                                  &out) == 2);
  CHECK_THAT(out, Contains("900 target points; expected at most 500"));
  // Before the subcommand as well as after it, and over the environment variable.
  CHECK(handeye::test::RunHandeye(
            "--max-target-points 500 target checkerboard --board 30x30 --square 0.002 -o " + dir + "/c.png", &out) == 2);
  CHECK(handeye::test::RunHandeye("target checkerboard --board 160x160 --square 0.001 -o " + dir + "/d.png", &out) == 2);
  CHECK(handeye::test::RunHandeye(
            "target checkerboard --board 160x160 --square 0.001 --max-target-points 3e4 -o " + dir + "/d.png", &out) == 0);
  for (const char* bad : {"0", "-5", "1.5", "many"}) {
    INFO(bad);
    CHECK(handeye::test::RunHandeye(std::string("target checkerboard --board 9x6 -o ") + dir +
                                        "/e.png --max-image-pixels " + bad,
                                    &out) == 2);
    CHECK_THAT(out, Contains("--max-image-pixels"));
    CHECK_THAT(out, Contains("expected a positive integer"));
  }
}
