// SPDX-License-Identifier: GPL-2.0-or-later
// Dataset and observation files (SPEC §4, §5): one test per kind of bad
// input, asserting that the message names the file, the JSON path and what
// was expected.
#include <catch2/catch.hpp>
#include <string>

#include "dataset_json_fixtures.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/dataset_json.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using namespace handeye::test;

TEST_CASE("Bad input: missing file", "[io][dataset][bad]") {
  const std::string file = test::TempDir("dataset_missing") + "/nope.json";
  try {
    LoadDataset(file);
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.file() == file);
    CHECK_THAT(e.what(), Contains(file + ": file does not exist"));
  }
}

TEST_CASE("Bad input: malformed JSON gives line and column", "[io][dataset][bad]") {
  std::string text = ValidDatasetJson().dump(2);
  const std::size_t at = text.find("\"setup\"");
  text.insert(at, "\"oops\" ");  // a key without colon and value
  const auto line = 1 + std::count(text.begin(), text.begin() + at, '\n');
  const std::string file = test::TempDir("dataset_malformed") + "/data.json";
  test::WriteText(file, text);
  try {
    LoadDataset(file);
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.file() == file);
    CHECK_THAT(e.what(), Contains("malformed JSON: parse error at line " + std::to_string(line) +
                                  ", column"));
  }
}

TEST_CASE("Bad input: wrong types", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["cameras"][1]["intrinsics"]["fx"] = "500";
  RequireLoadError(j, "/cameras/1/intrinsics/fx",
                   "expected a positive number, got the string \"500\"");

  j = ValidDatasetJson();
  j["cameras"][0]["image_size"] = {1920.5, 1080};
  RequireLoadError(j, "/cameras/0/image_size/0", "expected an integer between 1 and");

  j = ValidDatasetJson();
  j["poses"][2]["id"] = 3;
  RequireLoadError(j, "/poses/2/id", "expected a pose id (a non-empty string), got the number 3");

  j = ValidDatasetJson();
  j["poses"] = json::object();
  RequireLoadError(j, "/poses", "expected an array of robot pose objects, got an object");

  j = ValidDatasetJson();
  j["poses"][0]["T_base_ee"][1] = {0, 1, 0};
  RequireLoadError(j, "/poses/0/T_base_ee", "expected a 4x4 array of numbers");

  j = ValidDatasetJson();
  j["target"]["square_size_m"] = "0.05";
  RequireLoadError(j, "/target/square_size_m", "expected a positive number");
}

TEST_CASE("Bad input: missing keys", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["poses"][1].erase("T_base_ee");
  RequireLoadError(j, "/poses/1/T_base_ee", "missing key; expected a 4x4 array of numbers");

  j = ValidDatasetJson();
  j["cameras"][0].erase("distortion");
  RequireLoadError(j, "/cameras/0/distortion", "missing key; expected {\"model\": \"none\"}");

  j = ValidDatasetJson();
  j.erase("setup");
  RequireLoadError(j, "/setup", "missing key; expected a setup");

  j = ValidDatasetJson();
  j["target"].erase("square_size_m");
  RequireLoadError(j, "/target/square_size_m", "missing key; expected a positive number");

  j = ValidDatasetJson();
  j["poses"][0].erase("images");
  RequireLoadError(j, "/poses/0/images",
                   "missing key; expected an object {camera name: image path}");
}

TEST_CASE("Bad input: unknown keys where a typo is likely", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["camera"] = j["cameras"];
  RequireLoadError(j, "/camera", "unknown key 'camera' (did you mean 'cameras'?)");

  j = ValidDatasetJson();
  j["cameras"][1]["intrinsic"] = j["cameras"][1]["intrinsics"];
  RequireLoadError(j, "/cameras/1/intrinsic",
                   "unknown key 'intrinsic' (did you mean 'intrinsics'?)");

  j = ValidDatasetJson();
  j["cameras"][0]["intrinsics"]["f"] = 3;
  RequireLoadError(j, "/cameras/0/intrinsics/f", "unknown key 'f'");

  j = ValidDatasetJson();
  j["poses"][2]["T_base_EE"] = j["poses"][2]["T_base_ee"];
  RequireLoadError(j, "/poses/2/T_base_EE", "did you mean 'T_base_ee'?");

  j = ValidDatasetJson();
  j["target"]["square_size"] = 0.05;
  RequireLoadError(j, "/target/square_size", "unknown key");

  j = ValidDatasetJson();
  j["observations"] = json::array();  // only observation files have them
  RequireLoadError(j, "/observations", "unknown key 'observations'");
}

TEST_CASE("Bad input: duplicate key in one object", "[io][dataset][bad]") {
  std::string text = ValidDatasetJson().dump(2);
  const std::size_t at = text.find("\"T_base_ee\"");
  text.insert(at, "\"T_base_ee\": 0, ");
  const std::string file = test::TempDir("dataset_dupkey") + "/data.json";
  test::WriteText(file, text);
  try {
    LoadDataset(file);
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.json_path() == "/poses/0/T_base_ee");
    CHECK_THAT(e.what(), Contains(file + ": at /poses/0/T_base_ee: duplicate key 'T_base_ee'"));
  }
}

TEST_CASE("Bad input: non-rigid T_base_ee, accepted when reorthonormalising",
          "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["poses"][2]["T_base_ee"][0][1] = 1e-4;  // rotation now off orthonormal by 1e-4
  RequireLoadError(j, "/poses/2/T_base_ee", "off orthonormal");
  LoadOptions fix;
  fix.reorthonormalise = true;
  const std::string file = WriteJson(test::TempDir("dataset_reortho") + "/data.json", j);
  const Dataset d = LoadDataset(file, fix);
  CHECK(OrthonormalityError(d.poses[2].T_base_ee.linear()) < 1e-12);

  j = ValidDatasetJson();
  j["poses"][1]["T_base_ee"][0][0] = 2.0;  // far from any rotation: a mistake
  RequireLoadError(j, "/poses/1/T_base_ee", "expected a rigid 4x4 transform");

  j = ValidDatasetJson();
  j["poses"][1]["T_base_ee"][3] = {0, 0, 0, 2};
  RequireLoadError(j, "/poses/1/T_base_ee", "last row is [0, 0, 0, 1]", fix);

  j = ValidDatasetJson();
  j["poses"][0]["T_base_ee"][2][2] = -1.0;  // a reflection, not a rotation
  RequireLoadError(j, "/poses/0/T_base_ee", "reflection", fix);
}

TEST_CASE("Bad input: NaN and infinity", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["poses"][0]["T_base_ee"][0][3] = "nan";
  RequireLoadError(j, "/poses/0/T_base_ee/0/3", "got the string \"nan\"");

  j = ValidDatasetJson();
  j["cameras"][1]["distortion"]["coeffs"][2] = "inf";
  RequireLoadError(j, "/cameras/1/distortion/coeffs/2", "expected a finite number");

  // JSON has no NaN literal; a number too big for a double is how infinity sneaks in.
  std::string text = ValidDatasetJson().dump(2);
  text.replace(text.find("540.5"), 5, "1e999");
  const std::string file = test::TempDir("dataset_inf") + "/data.json";
  test::WriteText(file, text);
  try {
    LoadDataset(file);
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.file() == file);
    CHECK_THAT(e.what(),
               Contains("the number 1e999 does not fit a double; expected a finite number"));
    CHECK_THAT(e.what(), Contains("at line "));
  }
}

TEST_CASE("Bad input: wrong distortion coefficient count or model", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["cameras"][1]["distortion"]["coeffs"] = {0.1, 0.2, 0.3};
  RequireLoadError(j, "/cameras/1/distortion/coeffs",
                   "expected 4, 5, 8, 12 or 14 coefficients in OpenCV's order (k1, k2, p1, p2, k3, "
                   "k4, k5, k6, ...), got 3");

  j = ValidDatasetJson();
  j["cameras"][0]["distortion"]["coeffs"] = {0.1, 0.2, 0.3, 0.4};
  RequireLoadError(j, "/cameras/0/distortion/coeffs",
                   "expected no coefficients for model \"none\"");

  j = ValidDatasetJson();
  j["cameras"][0]["distortion"]["model"] = "fisheye";
  RequireLoadError(j, "/cameras/0/distortion/model", "unknown distortion model 'fisheye'");
}

TEST_CASE("Bad input: camera names duplicated or unusable", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["cameras"][1]["name"] = "cam0";
  RequireLoadError(j, "/cameras/1/name", "duplicate camera name 'cam0' (also at /cameras/0)");

  j = ValidDatasetJson();
  j["cameras"][1]["name"] = "a/b";
  RequireLoadError(j, "/cameras/1/name", "expected a camera name without '/'");

  j = ValidDatasetJson();
  j["cameras"] = json::array();
  RequireLoadError(j, "/cameras", "expected at least one camera");
}

TEST_CASE("Bad input: duplicate pose ids", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["poses"][2]["id"] = "0001";
  RequireLoadError(j, "/poses/2/id", "duplicate pose id '0001' (also at /poses/0)");
}

TEST_CASE("Bad input: image of an unknown camera", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["poses"][1]["images"]["cam7"] = "x.png";
  RequireLoadError(j, "/poses/1/images/cam7", "unknown camera 'cam7'; the cameras are: cam0, cam1");

  j = ValidDatasetJson();
  j["poses"][1]["images"]["cam0"] = "";
  RequireLoadError(j, "/poses/1/images/cam0", "expected an image path (a non-empty string)");
}

TEST_CASE("Bad input: observation of an unknown pose or camera", "[io][dataset][bad]") {
  json j = ValidObservationsJson();
  j["observations"][1]["pose"] = "0009";
  RequireLoadError(j, "/observations/1/pose", "unknown pose '0009'");

  j = ValidObservationsJson();
  j["observations"][2]["camera"] = "cam2";
  RequireLoadError(j, "/observations/2/camera",
                   "unknown camera 'cam2'; the cameras are: cam0, cam1");
}

TEST_CASE("Bad input: duplicate id in one observation", "[io][dataset][bad]") {
  json j = ValidObservationsJson();
  j["observations"][0]["ids"] = {0, 1, 0};
  RequireLoadError(j, "/observations/0/ids/2", "duplicate id 0 (also at /observations/0/ids/0)");
}

TEST_CASE("Bad input: id that is not a point of the target", "[io][dataset][bad]") {
  json j = ValidObservationsJson();
  j["observations"][1]["ids"][0] = 12;  // a 4x3 board has ids 0..11
  RequireLoadError(
      j, "/observations/1/ids/0",
      "id 12 is not a point of the 'checkerboard' target (its 12 points have ids 0..11)");

  j = ValidObservationsJson();
  j["observations"][1]["ids"][1] = -1;
  RequireLoadError(j, "/observations/1/ids/1", "expected an integer >= 0");
}

TEST_CASE("Bad input: ids and points_px of different lengths", "[io][dataset][bad]") {
  json j = ValidObservationsJson();
  j["observations"][0]["points_px"].erase(2);
  RequireLoadError(j, "/observations/0/points_px", "expected 3 pixels [u, v], one per id, got 2");

  j = ValidObservationsJson();
  j["observations"][0]["points_px"][1] = {3, 4, 5};
  RequireLoadError(j, "/observations/0/points_px/1",
                   "expected a pixel [u, v] of two finite numbers");

  j = ValidObservationsJson();
  j["observations"][0]["ids"] = json::array();
  j["observations"][0]["points_px"] = json::array();
  RequireLoadError(j, "/observations/0/ids", "expected at least one id");
}

TEST_CASE("Bad input: the same (pose, camera) observed twice", "[io][dataset][bad]") {
  json j = ValidObservationsJson();
  j["observations"].push_back(j["observations"][1]);
  RequireLoadError(
      j, "/observations/3",
      "duplicate observation of pose '0001' by camera 'cam1' (also at /observations/1)");
}

TEST_CASE("Bad input: unsupported format", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["format"] = "handeye-dataset/2";
  RequireLoadError(j, "/format",
                   "unsupported format 'handeye-dataset/2'; expected \"handeye-dataset/1\" or "
                   "\"handeye-observations/1\"");
  j.erase("format");
  RequireLoadError(j, "/format", "missing key; expected \"handeye-dataset/1\"");
  // An observations file lists no images.
  j = ValidObservationsJson();
  j["poses"][0]["images"] = json::object();
  RequireLoadError(j, "/poses/0/images", "unknown key 'images'; expected only: id, T_base_ee");
}

TEST_CASE("Bad input: wrong setup name", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["setup"] = "eye_on_base";
  RequireLoadError(j, "/setup",
                   "unknown setup 'eye_on_base'; expected \"eye_to_hand\" or \"eye_in_hand\"");
}

TEST_CASE("Bad input: unknown target type lists the known ones", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["target"]["type"] = "chessboard";
  std::string known;
  for (const auto& type : KnownTargetTypes()) known += (known.empty() ? "" : ", ") + type;
  RequireLoadError(j, "/target/type",
                   "unknown target type 'chessboard'; expected one of: " + known);
}

TEST_CASE("Bad input: a broken ground_truth object inside a dataset", "[io][dataset][bad]") {
  json j = ValidDatasetJson();
  j["ground_truth"] = json::parse(R"({"T_base_cam": {"cam0": [[1, 0], [0, 1]]}})");
  RequireLoadError(j, "/ground_truth/T_base_cam/cam0", "expected a 4x4 array of numbers");
}

}  // namespace
}  // namespace handeye

namespace handeye {
namespace {

using namespace handeye::test;

TEST_CASE("Bad input: a camera or board larger than the input caps", "[io][dataset][bad][limits]") {
  unsetenv("HANDEYE_MAX_IMAGE_PIXELS");
  unsetenv("HANDEYE_MAX_TARGET_POINTS");
  // A 4 MB PNG of 65536 x 65536 pixels decoded to 9.5 GB: its camera is
  // refused when the dataset loads, before detect reads an image.
  json j = ValidDatasetJson();
  j["cameras"][0]["image_size"] = {65536, 65536};
  RequireLoadError(j, "/cameras/0/image_size",
                   "65536 x 65536 = 4294967296 pixels; expected at most 200000000 per image "
                   "(raise it with --max-image-pixels or HANDEYE_MAX_IMAGE_PIXELS to allow larger images)");
  // The same board declared 20000 x 20000 asked for 12.5 GB.
  j = ValidDatasetJson();
  j["target"]["inner_corners"] = {20000, 20000};
  RequireLoadError(j, "/target/inner_corners",
                   "20000 x 20000 = 400000000 target points; expected at most 20000 "
                   "(raise it with --max-target-points or HANDEYE_MAX_TARGET_POINTS to allow a larger board)");
}

}  // namespace
}  // namespace handeye
