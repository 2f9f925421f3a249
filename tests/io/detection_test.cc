// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/detection.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <mutex>
#include <set>

#include "handeye/core/error.h"
#include "handeye/detectors/registry.h"
#include "io/io_fixtures.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;

constexpr int kCols = 5, kRows = 4, kSquarePx = 24, kWidth = 240, kHeight = 200;

// A dataset of `num_poses` poses × 2 cameras whose images are written by the
// caller; image paths are dir/<camera>/<pose>.png.
Dataset MakeDetectionDataset(const std::string& dir, int num_poses) {
  Dataset d;
  TargetSpec spec;
  spec.type = "checkerboard";
  spec.values["inner_corners"] = std::vector<double>{kCols, kRows};
  spec.values["square_size_m"] = 0.03;
  d.target = MakeTarget(spec);
  std::string why;
  for (const char* name : {"camA", "camB"})
    d.cameras.push_back(*Camera::Make(name, kWidth, kHeight, 300, 300, 120, 100, {}, &why));
  for (int p = 0; p < num_poses; ++p) {
    RobotPose pose;
    pose.id = "pose" + std::to_string(p);
    for (const auto& camera : d.cameras)
      pose.images[camera.name] = dir + "/" + camera.name + "/" + pose.id + ".png";
    d.poses.push_back(pose);
  }
  return d;
}

// Board origin of (pose, camera) in pixels, different for every view.
cv::Point Origin(int pose, int camera) {
  return cv::Point(40 + 7 * pose + 3 * camera, 50 + 5 * pose);
}

void WriteBoardImages(const Dataset& d, bool blank_pose1_camB) {
  for (std::size_t p = 0; p < d.poses.size(); ++p)
    for (std::size_t c = 0; c < d.cameras.size(); ++c) {
      const std::string& path = d.poses[p].images.at(d.cameras[c].name);
      test::WriteText(path, "");
      cv::Mat image;
      if (blank_pose1_camB && p == 1 && c == 1) {
        image = cv::Mat(kHeight, kWidth, CV_8UC1, cv::Scalar(128));
      } else {
        const cv::Point o = Origin(static_cast<int>(p), static_cast<int>(c));
        image = test::DrawBoard(kCols, kRows, kSquarePx, o.x, o.y, kWidth, kHeight);
      }
      REQUIRE(cv::imwrite(path, image));
    }
}

TEST_CASE("DetectAll finds the board in every view, in pose then camera order", "[io][detect]") {
  const std::string dir = test::TempDir("detect_all");
  Dataset d = MakeDetectionDataset(dir, 4);
  WriteBoardImages(d, true);
  for (int threads : {1, 3}) {
    std::vector<std::pair<std::size_t, std::size_t>> progress;
    std::mutex check_serial;
    bool overlapped = false;
    DetectOptions options;
    options.threads = threads;
    // Runs on worker threads, so no Catch assertions in here.
    options.progress = [&](std::size_t done, std::size_t total) {
      // Calls never overlap: try_lock would fail if another were running.
      if (!check_serial.try_lock()) {
        overlapped = true;
        return;
      }
      progress.emplace_back(done, total);
      check_serial.unlock();
    };
    d.observations = {Observation{}};  // replaced, not appended to
    DetectAll(&d, options);

    CHECK_FALSE(overlapped);
    REQUIRE(progress.size() == 8);
    for (std::size_t k = 0; k < progress.size(); ++k)
      CHECK(progress[k] == std::make_pair(k + 1, std::size_t{8}));

    // 8 images, one of them blank: 7 views, pose-major, camera order of the dataset.
    REQUIRE(d.observations.size() == 7);
    std::size_t k = 0;
    for (int p = 0; p < 4; ++p)
      for (int c = 0; c < 2; ++c) {
        if (p == 1 && c == 1) continue;
        const Observation& view = d.observations[k++];
        CHECK(view.pose_id == "pose" + std::to_string(p));
        CHECK(view.camera == d.cameras[c].name);
        REQUIRE(view.ids.size() == static_cast<std::size_t>(kCols * kRows));
        REQUIRE(view.points_px.size() == view.ids.size());
        // Ids follow SPEC §4 (the board is not ambiguous: 5 + 4 is odd).
        const cv::Point o = Origin(p, c);
        for (std::size_t n = 0; n < view.ids.size(); ++n) {
          const int id = view.ids[n];
          const Eigen::Vector2d expected =
              test::CornerPixel(id % kCols, id / kCols, kSquarePx, o.x, o.y);
          CHECK((view.points_px[n] - expected).norm() < 0.2);
        }
      }
  }
}

void RequireDetectError(Dataset* d, const std::string& file, const std::string& expected) {
  for (int threads : {1, 2}) {
    DetectOptions options;
    options.threads = threads;
    try {
      DetectAll(d, options);
    } catch (const InputError& e) {
      CHECK(e.file() == file);
      CHECK_THAT(e.what(), Contains(file));
      CHECK_THAT(e.what(), Contains(expected));
      continue;
    }
    FAIL("DetectAll accepted the dataset; expected an error about " + file);
  }
}

TEST_CASE("DetectAll: a missing image is an input error naming it", "[io][detect][bad]") {
  const std::string dir = test::TempDir("detect_missing");
  Dataset d = MakeDetectionDataset(dir, 3);
  WriteBoardImages(d, false);
  const std::string missing = d.poses[2].images.at("camA");
  std::filesystem::remove(missing);
  RequireDetectError(&d, missing, "image file does not exist");
}

TEST_CASE("DetectAll: an unreadable image is an input error naming it", "[io][detect][bad]") {
  const std::string dir = test::TempDir("detect_garbage");
  Dataset d = MakeDetectionDataset(dir, 3);
  WriteBoardImages(d, false);
  const std::string garbage = d.poses[1].images.at("camB");
  test::WriteText(garbage, "this is not a PNG file, just bytes with a .png name\n");
  RequireDetectError(&d, garbage, "unreadable image");
}

TEST_CASE("DetectAll: an image of the wrong size is an input error naming it",
          "[io][detect][bad]") {
  const std::string dir = test::TempDir("detect_size");
  Dataset d = MakeDetectionDataset(dir, 3);
  WriteBoardImages(d, false);
  const std::string wrong = d.poses[0].images.at("camB");
  REQUIRE(cv::imwrite(wrong, cv::Mat(kHeight, kWidth + 1, CV_8UC1, cv::Scalar(0))));
  RequireDetectError(&d, wrong, "image is 241x200 but camera 'camB' has image_size [240, 200]");
}

}  // namespace
}  // namespace handeye
