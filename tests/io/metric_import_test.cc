// SPDX-License-Identifier: GPL-2.0-or-later
// METRIC / original-tool folders (SPEC §8).
#include "handeye/io/metric_import.h"

#include <catch2/catch.hpp>
#include <filesystem>

#include "handeye/core/checkerboard.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "io/io_fixtures.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;
namespace fs = std::filesystem;

// Requires ImportMetricFolder to fail naming `file` (relative to `dir`) and saying `expected`.
void RequireImportError(const std::string& dir, const std::string& file,
                        const std::string& expected, const std::string& json_path = "") {
  try {
    ImportMetricFolder(dir);
  } catch (const InputError& e) {
    CHECK(e.file() == (fs::path(dir) / file).string());
    CHECK(e.json_path() == json_path);
    CHECK_THAT(e.what(), Contains(file));
    CHECK_THAT(e.what(), Contains(expected));
    return;
  }
  FAIL("ImportMetricFolder accepted the folder; expected an error in " + file);
}

TEST_CASE("METRIC folder: cameras, target, poses and ground truth", "[io][metric]") {
  const std::string dir = test::TempDir("metric_import");
  test::WriteMetricFolder(dir, 1, true);
  const MetricImport imported = ImportMetricFolder(dir);
  const Dataset& d = imported.dataset;

  CHECK(d.setup == Setup::kEyeToHand);  // calibration_setup 1 = eye-on-base
  // cv::Size(number_of_rows = 4, number_of_columns = 3): 4 corners per OpenCV
  // row, which are our cols.
  const auto* board = dynamic_cast<const CheckerboardTarget*>(d.target.get());
  REQUIRE(board);
  CHECK(board->cols() == 4);
  CHECK(board->rows() == 3);
  CHECK(board->square_size_m() == 0.05);

  REQUIRE(d.cameras.size() == 2);
  CHECK(d.cameras[0].name == "camera1");
  CHECK(d.cameras[0].width == 64);
  CHECK(d.cameras[0].height == 48);
  CHECK(d.cameras[0].fx() == 1360.5206198852188);
  CHECK(d.cameras[0].cy() == 23.25);
  // dist_k0 dist_k1 dist_px dist_py dist_k2 dist_k3 dist_k4 dist_k5 = OpenCV k1 k2 p1 p2 k3 k4 k5
  // k6.
  CHECK(d.cameras[0].Distortion() ==
        std::vector<double>{-0.01, 0.2, 0.003, -0.0002, -1.3, 0.01, 0.02, 0.03});
  CHECK(d.cameras[1].name == "camera2");
  CHECK(d.cameras[1].num_distortion == 0);  // has_dist_coeff: 0
  CHECK(d.cameras[1].fx() == 800);
  CHECK(d.cameras[1].width == 64);  // written as 64.0

  // Poses: the union of stems, sorted; the same stem is the same robot pose.
  REQUIRE(d.poses.size() == 4);
  for (int i = 0; i < 4; ++i) {
    const RobotPose& pose = d.poses[i];
    CHECK(pose.id == "000" + std::to_string(i + 1));
    CHECK((pose.T_base_ee.matrix() - test::MetricPose(i + 1).matrix()).cwiseAbs().maxCoeff() <
          1e-15);
  }
  const std::string abs_dir = fs::absolute(dir).lexically_normal().string();
  CHECK(d.poses[0].images.size() == 1);
  CHECK(d.poses[0].images.at("camera1") == abs_dir + "/camera1/image/0001.png");
  CHECK(d.poses[1].images.size() == 2);
  CHECK(d.poses[2].images.at("camera2") == abs_dir + "/camera2/image/0003.jpg");
  CHECK(d.poses[3].images.size() == 1);
  CHECK(d.poses[3].images.at("camera2") == abs_dir + "/camera2/image/0004.tiff");
  CHECK(d.observations.empty());

  REQUIRE(imported.truth);
  CHECK(imported.truth->setup == Setup::kEyeToHand);
  CHECK_FALSE(imported.truth->has_T_target);
  REQUIRE(imported.truth->T_cam.size() == 2);
  for (int k = 1; k <= 2; ++k)
    CHECK((imported.truth->T_cam.at("camera" + std::to_string(k)).matrix() -
           test::MetricCamera(k).matrix())
              .cwiseAbs()
              .maxCoeff() < 1e-15);
}

// Rewrites camera2's copy of pose 0003 moved by `dx_m` along x and turned by
// `angle_deg` about z, as the published folders' per-camera copies differ.
void MoveCamera2Pose3(const std::string& dir, double dx_m, double angle_deg) {
  Eigen::Isometry3d moved = test::MetricPose(3);
  moved.translation().x() += dx_m;
  moved.linear() = moved.linear() * Eigen::AngleAxisd(angle_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ());
  test::WriteText(dir + "/camera2/pose/0003.csv", test::MatrixText(moved.matrix(), ","));
}

TEST_CASE("METRIC folder: per-camera copies of a pose that differ by µm are one pose", "[io][metric]") {
  const std::string dir = test::TempDir("metric_import_um");
  test::WriteMetricFolder(dir, 1, false);
  // As in the published medium_workcell: 13 µm and 0.0036° between copies.
  MoveCamera2Pose3(dir, 13e-6, 0.0036);
  const MetricImport imported = ImportMetricFolder(dir);
  const Dataset& d = imported.dataset;
  REQUIRE(d.poses.size() == 4);
  const RobotPose& pose = d.poses[2];
  CHECK(pose.id == "0003");
  CHECK(pose.images.size() == 2);
  // The mean of the two copies: half the offset from camera1's.
  const Eigen::Isometry3d original = test::MetricPose(3);
  CHECK(std::abs(pose.T_base_ee.translation().x() - original.translation().x() - 6.5e-6) < 1e-9);
  CHECK(std::abs(RotationDistance(pose.T_base_ee.rotation(), original.rotation()) * 180.0 / M_PI -
                 0.0018) < 1e-6);
  CHECK(imported.warnings.empty());
  REQUIRE(imported.notes.size() == 1);
  CHECK_THAT(imported.notes[0], Contains("differ by up to 13 µm and 0.0036°"));
}

TEST_CASE("METRIC folder: copies of a pose that disagree stay separate poses", "[io][metric]") {
  const std::string dir = test::TempDir("metric_import_split");
  test::WriteMetricFolder(dir, 1, false);
  SECTION("by 1 mm") { MoveCamera2Pose3(dir, 1e-3, 0.0); }
  SECTION("by 0.05°") { MoveCamera2Pose3(dir, 0.0, 0.05); }
  const MetricImport imported = ImportMetricFolder(dir);
  const Dataset& d = imported.dataset;
  REQUIRE(d.poses.size() == 5);
  CHECK(d.poses[2].id == "0003_camera1");
  CHECK(d.poses[2].images.size() == 1);
  CHECK(d.poses[2].images.count("camera1") == 1);
  CHECK(d.poses[3].id == "0003_camera2");
  CHECK(d.poses[3].images.count("camera2") == 1);
  CHECK((d.poses[2].T_base_ee.matrix() - test::MetricPose(3).matrix()).cwiseAbs().maxCoeff() < 1e-15);
  REQUIRE(imported.warnings.size() == 1);
  CHECK(imported.warnings[0].kind == WarningKind::kPoseFilesDisagree);
  CHECK_THAT(imported.warnings[0].text, Contains("pose files named 0003 disagree"));
  CHECK_THAT(imported.warnings[0].text, Contains("camera2/pose/0003.csv"));
  CHECK_THAT(imported.warnings[0].text, Contains("each camera keeps its own record"));
}

TEST_CASE("METRIC YAML as cv::FileStorage writes it, with comments and quotes", "[io][metric]") {
  const std::string dir = test::TempDir("metric_filestorage");
  test::WriteMetricFolder(dir, 1, false);
  test::WriteText(dir + "/CalibrationInfo.yaml",
                  "%YAML:1.0\n---\n# Number of cameras\nnumber_of_cameras: 2\n"
                  "camera_folder_prefix: \"camera\"\npattern_type: 'checkerboard'  # the only one\n"
                  "number_of_rows: 4\nnumber_of_columns: 3\nsize: 5.0e-02\nresize_factor: 1\n"
                  "visual_error: 1\ncalibration_setup: 1\n");
  const MetricImport imported = ImportMetricFolder(dir);
  CHECK(imported.dataset.cameras.size() == 2);
  const auto* board = dynamic_cast<const CheckerboardTarget*>(imported.dataset.target.get());
  REQUIRE(board);
  CHECK(board->square_size_m() == 0.05);
}

TEST_CASE("METRIC folder without GT, eye-in-hand", "[io][metric]") {
  const std::string dir = test::TempDir("metric_import_eih");
  test::WriteMetricFolder(dir, 0, false);
  const MetricImport imported = ImportMetricFolder(dir);
  CHECK(imported.dataset.setup == Setup::kEyeInHand);
  CHECK_FALSE(imported.truth);
}

TEST_CASE("METRIC folder: bad input names the file and what was expected", "[io][metric][bad]") {
  const std::string dir = test::TempDir("metric_bad");

  SECTION("no such folder") {
    try {
      ImportMetricFolder(dir + "/nope");
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(e.file() == dir + "/nope");
      CHECK_THAT(e.what(), Contains("folder does not exist"));
    }
  }
  SECTION("missing CalibrationInfo.yaml") {
    test::WriteMetricFolder(dir, 1, false);
    fs::remove(dir + "/CalibrationInfo.yaml");
    RequireImportError(dir, "CalibrationInfo.yaml", "file does not exist");
  }
  SECTION("missing pose file for an image") {
    test::WriteMetricFolder(dir, 1, false);
    fs::remove(dir + "/camera2/pose/0003.csv");
    RequireImportError(dir, "camera2/pose/0003.csv",
                       "pose file does not exist; expected one per image with the same name stem");
  }
  SECTION("a pose file that is not 4x4") {
    test::WriteMetricFolder(dir, 1, false);
    test::WriteText(dir + "/camera1/pose/0002.csv", "1 0 0 0\n0 1 0 0\n0 0 1 0\n");
    RequireImportError(dir, "camera1/pose/0002.csv", "expected a 4x4 matrix");
    test::WriteText(dir + "/camera1/pose/0002.csv", "1 0 0 0\n0 1 0 0\n0 0 1 0 7\n0 0 0 1\n");
    RequireImportError(dir, "camera1/pose/0002.csv", "line 3 has 5 values");
  }
  SECTION("a pose file with a non-number") {
    test::WriteMetricFolder(dir, 1, false);
    test::WriteText(dir + "/camera1/pose/0002.csv", "1,0,0,0\n0,1,0,0\n0,0,1,nan\n0,0,0,1\n");
    RequireImportError(dir, "camera1/pose/0002.csv",
                       "line 3, value 4: expected a finite number, got 'nan'");
  }
  SECTION("a pose file that is not rigid") {
    test::WriteMetricFolder(dir, 1, false);
    test::WriteText(dir + "/camera1/pose/0001.csv", "1 0 0 0\n0 1 0.01 0\n0 0 1 0\n0 0 0 1\n");
    RequireImportError(dir, "camera1/pose/0001.csv", "expected a rigid 4x4 transform");
  }
  SECTION("a missing key in CalibrationInfo.yaml") {
    test::WriteMetricFolder(dir, 1, false);
    test::WriteText(
        dir + "/CalibrationInfo.yaml",
        "number_of_cameras: 2\ncamera_folder_prefix: camera\npattern_type: checkerboard\n"
        "number_of_rows: 4\nsize: 0.05\ncalibration_setup: 1\n");
    RequireImportError(dir, "CalibrationInfo.yaml", "missing key; expected an integer",
                       "/number_of_columns");
  }
  SECTION("a bad value in CalibrationInfo.yaml") {
    test::WriteMetricFolder(dir, 1, false);
    test::WriteText(
        dir + "/CalibrationInfo.yaml",
        "number_of_cameras: 2\ncamera_folder_prefix: camera\npattern_type: checkerboard\n"
        "number_of_rows: 4\nnumber_of_columns: 3.5\nsize: 0.05\ncalibration_setup: 1\n");
    RequireImportError(dir, "CalibrationInfo.yaml", "got '3.5' (line 5)", "/number_of_columns");
  }
  SECTION("an unsupported pattern") {
    test::WriteMetricFolder(dir, 1, false);
    test::WriteText(dir + "/CalibrationInfo.yaml",
                    "number_of_cameras: 2\ncamera_folder_prefix: camera\npattern_type: charuco\n"
                    "number_of_rows: 4\nnumber_of_columns: 3\nsize: 0.05\ncalibration_setup: 1\n");
    RequireImportError(dir, "CalibrationInfo.yaml", "unsupported pattern_type 'charuco'",
                       "/pattern_type");
  }
  SECTION("a camera folder prefix that is a path") {
    test::WriteMetricFolder(dir, 1, false);
    test::WriteText(dir + "/CalibrationInfo.yaml",
                    "number_of_cameras: 2\ncamera_folder_prefix: cams/camera\n"
                    "pattern_type: checkerboard\nnumber_of_rows: 4\nnumber_of_columns: 3\n"
                    "size: 0.05\ncalibration_setup: 1\n");
    RequireImportError(dir, "CalibrationInfo.yaml", "without '/'", "/camera_folder_prefix");
  }
  SECTION("a line that is not key: value") {
    test::WriteMetricFolder(dir, 1, false);
    test::WriteText(dir + "/camera2/intrinsic_pars_file.yaml", "fx 800\n");
    RequireImportError(dir, "camera2/intrinsic_pars_file.yaml", "line 1: expected 'key: value'");
  }
  SECTION("a nested value, a duplicate key and broken YAML in CalibrationInfo.yaml") {
    test::WriteMetricFolder(dir, 1, false);
    const std::string keys =
        "number_of_cameras: 2\ncamera_folder_prefix: camera\npattern_type: checkerboard\n"
        "number_of_rows: 4\nnumber_of_columns: 3\ncalibration_setup: 1\n";
    test::WriteText(dir + "/CalibrationInfo.yaml", keys + "size:\n  metres: 0.05\n");
    RequireImportError(dir, "CalibrationInfo.yaml", "line 7: nested YAML is not supported", "/size");
    test::WriteText(dir + "/CalibrationInfo.yaml", keys + "size: 0.05\nnumber_of_rows: 5\n");
    RequireImportError(dir, "CalibrationInfo.yaml", "duplicate key on line 8 (also on line 4)",
                       "/number_of_rows");
    test::WriteText(dir + "/CalibrationInfo.yaml", keys + "size: [0.05\n");
    RequireImportError(dir, "CalibrationInfo.yaml", "line 8: end of sequence flow not found");
  }
  SECTION("has_dist_coeff without the coefficients") {
    test::WriteMetricFolder(dir, 1, false);
    test::WriteText(dir + "/camera2/intrinsic_pars_file.yaml",
                    "fx: 800\nfy: 800\ncx: 32\ncy: 24\nhas_dist_coeff: 1\nimg_width: 64\n"
                    "img_height: 48\n");
    RequireImportError(dir, "camera2/intrinsic_pars_file.yaml", "missing key", "/dist_k0");
  }
  SECTION("a missing camera folder") {
    test::WriteMetricFolder(dir, 1, false);
    fs::remove_all(dir + "/camera2");
    RequireImportError(dir, "camera2", "camera folder does not exist");
  }
  SECTION("a camera without images") {
    test::WriteMetricFolder(dir, 1, false);
    for (const char* name : {"0002.png", "0003.jpg", "0004.tiff"})
      fs::remove(dir + "/camera2/image/" + name);
    RequireImportError(dir, "camera2/image", "no images");
  }
  SECTION("two images with one stem") {
    test::WriteMetricFolder(dir, 1, false);
    test::WriteGrayPng(dir + "/camera1/image/0002.jpg", 64, 48);
    RequireImportError(dir, "camera1/image/0002.png", "two images share the name stem '0002'");
  }
  SECTION("an incomplete GT folder") {
    test::WriteMetricFolder(dir, 1, true);
    fs::remove(dir + "/GT/gt_cam2.csv");
    RequireImportError(dir, "GT/gt_cam2.csv", "ground-truth file does not exist");
  }
  SECTION("GT with eye-in-hand") {
    test::WriteMetricFolder(dir, 0, true);
    RequireImportError(dir, "GT", "only defined for calibration_setup 1");
  }
}

}  // namespace
}  // namespace handeye
