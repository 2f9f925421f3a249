// SPDX-License-Identifier: GPL-2.0-or-later
// Intrinsics by reference (io/intrinsics_files.h): OpenCV FileStorage
// YAML/XML, ROS camera_info (calibration file, ROS 1 and ROS 2 message) and
// Kalibr camchains, read alone and through a dataset's `intrinsics_file`.
#include "handeye/io/intrinsics_files.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "handeye/core/error.h"
#include "handeye/io/dataset_json.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;
using nlohmann::json;

const std::vector<double> kPlumbBob = {-0.1, 0.01, 0.001, -0.002, 0.0003};

// As OpenCV's calibration sample writes it, through cv::FileStorage.
void WriteOpenCv(const std::string& path) {
  cv::FileStorage fs(path, cv::FileStorage::WRITE);
  fs << "image_width" << 640 << "image_height" << 480;
  fs << "camera_matrix" << (cv::Mat_<double>(3, 3) << 520.1234567890123, 0, 320.5, 0, 521.75, 240.25, 0, 0, 1);
  fs << "distortion_coefficients" << cv::Mat(kPlumbBob).t();
}

const char kRosCalibrationFile[] = R"(image_width: 640
image_height: 480
camera_name: narrow_stereo
camera_matrix:
  rows: 3
  cols: 3
  data: [520.1234567890123, 0, 320.5, 0, 521.75, 240.25, 0, 0, 1]
distortion_model: plumb_bob
distortion_coefficients:
  rows: 1
  cols: 5
  data: [-0.1, 0.01, 0.001, -0.002, 0.0003]
rectification_matrix:
  rows: 3
  cols: 3
  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]
projection_matrix:
  rows: 3
  cols: 4
  data: [515.2, 0, 321.1, 0, 0, 518.3, 239.9, 0, 0, 0, 1, 0]
)";

// `ros2 topic echo --once /camera_info`: lowercase keys, block sequences at
// the key's indentation, a trailing document marker.
const char kRos2Message[] = R"(header:
  stamp:
    sec: 1700000000
    nanosec: 5000
  frame_id: camera_optical_frame
height: 480
width: 640
distortion_model: plumb_bob
d:
- -0.1
- 0.01
- 0.001
- -0.002
- 0.0003
k:
- 520.1234567890123
- 0.0
- 320.5
- 0.0
- 521.75
- 240.25
- 0.0
- 0.0
- 1.0
r:
- 1.0
- 0.0
- 0.0
- 0.0
- 1.0
- 0.0
- 0.0
- 0.0
- 1.0
p: [515.2, 0.0, 321.1, 0.0, 0.0, 518.3, 239.9, 0.0, 0.0, 0.0, 1.0, 0.0]
binning_x: 0
binning_y: 0
roi:
  x_offset: 0
  y_offset: 0
  height: 0
  width: 0
  do_rectify: false
---
)";

// `rostopic echo -n 1 /camera_info` (ROS 1): uppercase, flow sequences.
const char kRos1Message[] = R"(header:
  seq: 42
  stamp:
    secs: 1700000000
    nsecs:         0
  frame_id: "camera"
height: 480
width: 640
distortion_model: "plumb_bob"
D: [-0.1, 0.01, 0.001, -0.002, 0.0003]
K: [520.1234567890123, 0.0, 320.5, 0.0, 521.75, 240.25, 0.0, 0.0, 1.0]
R: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
P: [515.2, 0.0, 321.1, 0.0, 0.0, 518.3, 239.9, 0.0, 0.0, 0.0, 1.0, 0.0]
binning_x: 0
binning_y: 0
roi:
  x_offset: 0
  y_offset: 0
  height: 0
  width: 0
  do_rectify: False
---
)";

// A Kalibr camchain as kalibr_calibrate_cameras writes it.
const char kKalibrCamchain[] = R"(cam0:
  cam_overlaps: [1]
  camera_model: pinhole
  distortion_coeffs: [-0.28340811217029355, 0.07395907389290132, 0.00019359502856909603, 1.7618711454538528e-05]
  distortion_model: radtan
  intrinsics: [458.6548807207614, 457.2966964634893, 367.2158039615726, 248.37534060980727]
  resolution: [752, 480]
  rostopic: /cam0/image_raw
cam1:
  T_cn_cnm1:
  - [0.9999972564778793, 0.002312067192424355, 0.0003760081024156567, -0.11007380812153212]
  - [-0.0023171357230958076, 0.9998980485066046, 0.014089835846681169, 0.0003991215470826699]
  - [-0.00034342354940638226, -0.014090361272014976, 0.9999006662129784, -0.0008537720467933446]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [0]
  camera_model: pinhole
  distortion_coeffs: [-0.2833940785441052, 0.07395907389290132, -0.00010473981456817, -3.555907745415498e-05]
  distortion_model: radtan
  intrinsics: [457.5874266035361, 456.13442556023665, 379.9994465203525, 255.2381853862733]
  resolution: [752, 480]
  rostopic: /cam1/image_raw
)";

void CheckPlumbBobCamera(const FileIntrinsics& in, bool with_size) {
  CHECK(in.fx == 520.1234567890123);
  CHECK(in.fy == 521.75);
  CHECK(in.cx == 320.5);
  CHECK(in.cy == 240.25);
  CHECK(in.distortion == kPlumbBob);
  if (with_size) {
    REQUIRE(in.image_size);
    CHECK((*in.image_size == std::array<int, 2>{640, 480}));
  } else {
    CHECK(!in.image_size);
  }
}

void RequireFileError(const std::string& path, IntrinsicsFileFormat format, const std::string& camera,
                      const std::string& json_path, const std::string& expected) {
  try {
    ReadIntrinsicsFile(path, format, camera);
  } catch (const InputError& e) {
    CHECK(e.file() == path);
    CHECK(e.json_path() == json_path);
    CHECK_THAT(e.what(), Contains(expected));
    return;
  }
  FAIL("accepted " + path + "; expected an error at '" + json_path + "': " + expected);
}

TEST_CASE("OpenCV FileStorage intrinsics: YAML, XML and YAML without the header", "[io][intrinsics]") {
  const std::string dir = test::TempDir("intrinsics_opencv");
  WriteOpenCv(dir + "/cam.yaml");
  WriteOpenCv(dir + "/cam.xml");
  CheckPlumbBobCamera(ReadIntrinsicsFile(dir + "/cam.yaml", IntrinsicsFileFormat::kOpenCv), true);
  CheckPlumbBobCamera(ReadIntrinsicsFile(dir + "/cam.xml", IntrinsicsFileFormat::kOpenCv), true);

  test::WriteText(dir + "/plain.yml",
                  "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                  "   data: [ 520.1234567890123, 0., 320.5, 0., 521.75, 240.25, 0., 0., 1. ]\n"
                  "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
                  "   data: [ -0.1, 0.01, 0.001, -0.002, 0.0003 ]\n");
  CheckPlumbBobCamera(ReadIntrinsicsFile(dir + "/plain.yml", IntrinsicsFileFormat::kOpenCv), false);

  test::WriteText(dir + "/skew.yml",
                  "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                  "   data: [ 520., 0.5, 320.5, 0., 521.75, 240.25, 0., 0., 1. ]\n"
                  "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: d\n"
                  "   data: [ 0., 0., 0., 0. ]\n");
  RequireFileError(dir + "/skew.yml", IntrinsicsFileFormat::kOpenCv, "", "/camera_matrix", "skew");
  test::WriteText(dir + "/no_dist.yml",
                  "%YAML:1.0\ncamera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                  "   data: [ 520., 0., 320.5, 0., 521.75, 240.25, 0., 0., 1. ]\n");
  RequireFileError(dir + "/no_dist.yml", IntrinsicsFileFormat::kOpenCv, "", "/distortion_coefficients",
                   "missing key");
  test::WriteText(dir + "/three.yml",
                  "%YAML:1.0\ncamera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                  "   data: [ 520., 0., 320.5, 0., 521.75, 240.25, 0., 0., 1. ]\n"
                  "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 3\n   dt: d\n"
                  "   data: [ 0., 0., 0. ]\n");
  RequireFileError(dir + "/three.yml", IntrinsicsFileFormat::kOpenCv, "", "/distortion_coefficients",
                   "expected 0, 4, 5, 8, 12 or 14 distortion coefficients");
  RequireFileError(dir + "/missing.yml", IntrinsicsFileFormat::kOpenCv, "", "", "file does not exist");
}

TEST_CASE("OpenCV FileStorage: a matrix header that lies is refused before OpenCV allocates it",
          "[io][intrinsics][bad]") {
  const std::string dir = test::TempDir("intrinsics_opencv_huge");
  const std::string K = "camera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n"
                        "  data: [800, 0, 320, 0, 800, 240, 0, 0, 1]\n";
  // fuzz/run found this: cv::read allocated rows x cols (16 GB) from the
  // header before reading the 4 values of data.
  for (const char* cols : {"2147483647", "65", "5"}) {
    test::WriteText(dir + "/huge.yml", K + "distortion_coefficients: !!opencv-matrix\n  rows: 1\n  cols: " +
                                           cols + "\n  dt: d\n  data: [0.1, -0.01, 0, 0]\n");
    INFO(cols);
    RequireFileError(dir + "/huge.yml", IntrinsicsFileFormat::kOpenCv, "", "/distortion_coefficients",
                     "expected an opencv-matrix (rows, cols, dt, data) of at most 64 x 64 single-channel values, "
                     "with rows x cols of them in data");
  }
  // Another one: a root that is not a mapping made OpenCV assert. The saved
  // input has NUL bytes, now refused before OpenCV parses it; a YAML list is
  // refused before OpenCV reads it too.
  RequireFileError((std::filesystem::path(HANDEYE_TEST_SOURCE_DIR "/io") / "fuzz_findings/opencv_root_not_a_map.yaml").string(),
                   IntrinsicsFileFormat::kOpenCv, "", "", "not a text file: a NUL byte at offset 8");
  test::WriteText(dir + "/list.yml", "%YAML:1.0\n- 1\n- 2\n");
  RequireFileError(dir + "/list.yml", IntrinsicsFileFormat::kOpenCv, "", "", "expected a mapping");
  // OpenCV's YAML parser threw std::length_error on a key with no name: the
  // input fuzz/run saved, and the three lines that are enough.
  for (const char* name : {"intrinsics_opencv_length_error.yaml", "opencv_yaml_empty_key.yaml"}) {
    INFO(name);
    RequireFileError((std::filesystem::path(HANDEYE_TEST_SOURCE_DIR "/io") / "fuzz_findings" / name).string(),
                     IntrinsicsFileFormat::kOpenCv, "", "", "not an OpenCV FileStorage file (YAML, XML or JSON)");
  }
  // OpenCV's XML parser read a null pointer when the text ended just after
  // an attribute's '=', also when a NUL byte ended it there.
  const auto finding_file = [](const char* name) {
    return (std::filesystem::path(HANDEYE_TEST_SOURCE_DIR "/io") / "fuzz_findings" / name).string();
  };
  RequireFileError(finding_file("intrinsics_opencv_xml_segv.xml"), IntrinsicsFileFormat::kOpenCv, "", "",
                   "not a text file: a NUL byte at offset 14");
  RequireFileError(finding_file("opencv_xml_nul_after_equals.xml"), IntrinsicsFileFormat::kOpenCv, "", "",
                   "not a text file: a NUL byte at offset");
  RequireFileError(finding_file("opencv_xml_ends_after_equals.xml"), IntrinsicsFileFormat::kOpenCv, "", "",
                   "not an OpenCV FileStorage XML file: it does not end with a closing tag");
  // OpenCV looped for ever on a base64 value (the saved input, then the
  // three formats' spellings); names that merely contain "binary" still read.
  RequireFileError(finding_file("opencv_yaml_binary_loops.yaml"), IntrinsicsFileFormat::kOpenCv, "", "",
                   "base64 (binary) values are not read: write the matrices as text");
  const std::string zeros(36, 'A');
  const std::string xml_head = "<?xml version=\"1.0\"?>\n<opencv_storage>\n";
  for (const std::string& text :
       {"a: !!binary " + zeros + "\n", "a: !<tag:yaml.org,2002:binary> " + zeros + "\n",
        "{\"a\": \"$base64$" + zeros + "\"}", xml_head + "<a type_id=\"binary\">" + zeros + "</a>\n</opencv_storage>\n",
        xml_head + "<a type_id = 'binary'>" + zeros + "</a>\n</opencv_storage>\n"}) {
    INFO(text);
    test::WriteText(dir + "/base64.txt", text);
    RequireFileError(dir + "/base64.txt", IntrinsicsFileFormat::kOpenCv, "", "", "base64 (binary) values are not read");
  }
  test::WriteText(dir + "/binary_name.yml", "%YAML:1.0\ncamera_name: binary_cam\nnote: \"binary\"\n" + K +
                                               "distortion_coefficients: !!opencv-matrix\n  rows: 1\n  cols: 4\n"
                                               "  dt: d\n  data: [0.1, -0.01, 0, 0]\n");
  ReadIntrinsicsFile(dir + "/binary_name.yml", IntrinsicsFileFormat::kOpenCv, "");
  // OpenCV looped for ever when the text went on after its first collection
  // with a '-' that does not start "---": the saved input, then the two ways
  // there (a line indented less than the first key, content after "...").
  RequireFileError(finding_file("opencv_yaml_indent_loops.yaml"), IntrinsicsFileFormat::kOpenCv, "", "",
                   "line 4: indented less than the first key (line 2)");
  RequireFileError(finding_file("opencv_yaml_streams_loop.yaml"), IntrinsicsFileFormat::kOpenCv, "", "",
                   "line 2: expected '---' alone on its line");
  for (const auto& [text, expected] :
       {std::pair<std::string, std::string>{" s: 3\nabc-\nr", "line 2: indented less than the first key (line 1)"},
        {"%YAML:1.0\n---\n  a: 1\n  b: 2\n c-\n", "line 5: indented less than the first key (line 3)"},
        {"a: 1\n...\n-x\n", "line 3: more after the document end ('...') on line 2"},
        {"a: 1\n...\n# c\n-\n", "line 4: more after the document end ('...') on line 2"},
        {"---\n---\na: 1\n", "line 2: a second YAML document ('---'); expected one document"},
        {"a: 1\n---\n-\n", "line 2: a second YAML document ('---'); expected one document"},
        {"----%-\na: 1\n", "line 1: expected '---' alone on its line"},
        {"%YAML:1.0\n- 1\n- 2\n", "line 2: expected a mapping (camera_matrix: ...), got a sequence"},
        {"[1]\n-x\n", "line 1: expected a mapping (camera_matrix: ...), got a sequence"}}) {
    INFO(text);
    test::WriteText(dir + "/loops.yml", text);
    RequireFileError(dir + "/loops.yml", IntrinsicsFileFormat::kOpenCv, "", "", expected);
  }
  // A file that ends with "...", comments anywhere and a nested key's
  // dedent still read.
  test::WriteText(dir + "/ends.yml", "%YAML:1.0\n---\n# intrinsics\n" + K +
                                         "   # a comment left of the keys\n"
                                         "distortion_coefficients: !!opencv-matrix\n  rows: 1\n  cols: 4\n"
                                         "  dt: d\n  data: [0.1, -0.01, 0, 0]\n...\n\n# end\n");
  ReadIntrinsicsFile(dir + "/ends.yml", IntrinsicsFileFormat::kOpenCv, "");
  // And one for the Kalibr reader: yaml-cpp's LoadAll never returned.
  RequireFileError((std::filesystem::path(HANDEYE_TEST_SOURCE_DIR "/io") / "fuzz_findings/kalibr_yaml_no_progress.yaml").string(),
                   IntrinsicsFileFormat::kKalibr, "cam0", "", "not readable as YAML (the parser gets no further)");
  // The input fuzz/run saved, as it was.
  const std::string finding =
      (std::filesystem::path(HANDEYE_TEST_SOURCE_DIR "/io") / "fuzz_findings/intrinsics_opencv_huge_cols.yaml").string();
  RequireFileError(finding, IntrinsicsFileFormat::kOpenCv, "", "/distortion_coefficients", "of at most 64 x 64");
}

TEST_CASE("ROS camera_info: calibration file, ROS 2 and ROS 1 messages", "[io][intrinsics]") {
  const std::string dir = test::TempDir("intrinsics_ros");
  test::WriteText(dir + "/calibration.yaml", kRosCalibrationFile);
  test::WriteText(dir + "/ros2.yaml", kRos2Message);
  test::WriteText(dir + "/ros1.yaml", kRos1Message);
  for (const char* name : {"calibration.yaml", "ros2.yaml", "ros1.yaml"}) {
    INFO(name);
    CheckPlumbBobCamera(ReadIntrinsicsFile(dir + "/" + name, IntrinsicsFileFormat::kRos), true);
  }

  std::string text = kRosCalibrationFile;
  text.replace(text.find("plumb_bob"), 9, "equidistant");
  test::WriteText(dir + "/fisheye.yaml", text);
  RequireFileError(dir + "/fisheye.yaml", IntrinsicsFileFormat::kRos, "", "/distortion_model",
                   "unsupported distortion model 'equidistant'");
  text = kRosCalibrationFile;
  text.replace(text.find("plumb_bob"), 9, "rational_polynomial");
  test::WriteText(dir + "/rational.yaml", text);
  RequireFileError(dir + "/rational.yaml", IntrinsicsFileFormat::kRos, "", "/distortion_coefficients",
                   "expected 8 coefficients for rational_polynomial, got 5");
  text = kRos2Message;
  text.replace(text.find("binning_x: 0"), 12, "binning_x: 2");
  test::WriteText(dir + "/binned.yaml", text);
  RequireFileError(dir + "/binned.yaml", IntrinsicsFileFormat::kRos, "", "/binning_x", "binning is not supported");
  test::WriteText(dir + "/neither.yaml", "width: 640\nheight: 480\n");
  RequireFileError(dir + "/neither.yaml", IntrinsicsFileFormat::kRos, "", "",
                   "expected a ROS camera_info: camera_matrix and distortion_coefficients");
  test::WriteText(dir + "/short.yaml", "K: [1, 0, 0, 0, 1, 0, 0, 0]\nD: []\ndistortion_model: plumb_bob\n");
  RequireFileError(dir + "/short.yaml", IntrinsicsFileFormat::kRos, "", "/K", "an array of 9 numbers");
}

TEST_CASE("Kalibr camchain: one camera by name, radtan = OpenCV k1 k2 p1 p2", "[io][intrinsics]") {
  const std::string dir = test::TempDir("intrinsics_kalibr");
  test::WriteText(dir + "/camchain.yaml", kKalibrCamchain);
  const FileIntrinsics cam1 = ReadIntrinsicsFile(dir + "/camchain.yaml", IntrinsicsFileFormat::kKalibr, "cam1");
  CHECK(cam1.fx == 457.5874266035361);
  CHECK(cam1.fy == 456.13442556023665);
  CHECK(cam1.cx == 379.9994465203525);
  CHECK(cam1.cy == 255.2381853862733);
  CHECK(cam1.distortion ==
        std::vector<double>{-0.2833940785441052, 0.07395907389290132, -0.00010473981456817, -3.555907745415498e-05});
  REQUIRE(cam1.image_size);
  CHECK((*cam1.image_size == std::array<int, 2>{752, 480}));

  RequireFileError(dir + "/camchain.yaml", IntrinsicsFileFormat::kKalibr, "cam2", "",
                   "no camera 'cam2' in the camchain; it has: cam0, cam1");
  RequireFileError(dir + "/camchain.yaml", IntrinsicsFileFormat::kKalibr, "", "", "the camera name");
  std::string text = kKalibrCamchain;
  text.replace(text.find("radtan"), 6, "equidistant");
  test::WriteText(dir + "/fisheye.yaml", text);
  RequireFileError(dir + "/fisheye.yaml", IntrinsicsFileFormat::kKalibr, "cam0", "/cam0/distortion_model",
                   "unsupported distortion model 'equidistant'");
  text = kKalibrCamchain;
  text.replace(text.find("camera_model: pinhole"), 21, "camera_model: omni");
  test::WriteText(dir + "/omni.yaml", text);
  RequireFileError(dir + "/omni.yaml", IntrinsicsFileFormat::kKalibr, "cam0", "/cam0/camera_model",
                   "unsupported camera model 'omni'");
}

json DatasetWithCamera(const json& camera) {
  json doc = json::parse(R"({
    "format": "handeye-dataset/1", "setup": "eye_to_hand",
    "target": {"type": "checkerboard", "inner_corners": [4, 3], "square_size_m": 0.05},
    "poses": [{"id": "1", "T_base_ee": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "images": {}}]
  })");
  doc["cameras"] = json::array({camera});
  return doc;
}

TEST_CASE("Dataset cameras reference intrinsics files by path", "[io][intrinsics][dataset]") {
  const std::string dir = test::TempDir("intrinsics_dataset");
  test::WriteText(dir + "/calib/ros.yaml", kRosCalibrationFile);
  test::WriteText(dir + "/calib/camchain.yaml", kKalibrCamchain);
  WriteOpenCv(dir + "/calib/opencv.xml");
  json doc = DatasetWithCamera({{"name", "ros_cam"}, {"intrinsics_file", {{"path", "calib/ros.yaml"}, {"format", "ros"}}}});
  doc["cameras"].push_back(
      {{"name", "kalibr_cam"},
       {"image_size", {752, 480}},
       {"intrinsics_file", {{"path", "calib/camchain.yaml"}, {"format", "kalibr"}, {"camera", "cam0"}}}});
  doc["cameras"].push_back(
      {{"name", "cv_cam"}, {"intrinsics_file", {{"path", dir + "/calib/opencv.xml"}, {"format", "opencv"}}}});
  test::WriteText(dir + "/dataset.json", doc.dump(2));
  const Dataset d = LoadDataset(dir + "/dataset.json");
  REQUIRE(d.cameras.size() == 3);
  CHECK(d.cameras[0].width == 640);
  CHECK(d.cameras[0].height == 480);
  CHECK(d.cameras[0].fx() == 520.1234567890123);
  CHECK(d.cameras[0].Distortion() == kPlumbBob);
  CHECK(d.cameras[1].fx() == 458.6548807207614);
  CHECK(d.cameras[1].cy() == 248.37534060980727);
  CHECK(d.cameras[1].num_distortion == 4);
  CHECK(d.cameras[1].width == 752);
  CHECK(d.cameras[2].cx() == 320.5);
  CHECK(d.cameras[2].Distortion() == kPlumbBob);

  auto require_error = [&](const json& camera, const std::string& file, const std::string& json_path,
                           const std::string& expected) {
    test::WriteText(dir + "/bad.json", DatasetWithCamera(camera).dump(2));
    try {
      LoadDataset(dir + "/bad.json");
    } catch (const InputError& e) {
      CHECK(e.file() == file);
      CHECK(e.json_path() == json_path);
      CHECK_THAT(e.what(), Contains(expected));
      return;
    }
    FAIL("accepted camera " + camera.dump());
  };
  const json ros_ref = {{"path", "calib/ros.yaml"}, {"format", "ros"}};
  require_error({{"name", "c"},
                 {"intrinsics_file", ros_ref},
                 {"intrinsics", {{"fx", 1}, {"fy", 1}, {"cx", 0}, {"cy", 0}}}},
                dir + "/bad.json", "/cameras/0/intrinsics",
                "give either intrinsics and distortion, or intrinsics_file; found both");
  require_error({{"name", "c"}, {"intrinsics_file", ros_ref}, {"image_size", {1280, 960}}}, dir + "/bad.json",
                "/cameras/0/image_size", "image_size [1280, 960] differs from the intrinsics file's [640, 480]");
  require_error({{"name", "c"}, {"intrinsics_file", {{"path", "calib/ros.yaml"}}}}, dir + "/bad.json",
                "/cameras/0/intrinsics_file/format", "missing key");
  require_error({{"name", "c"}, {"intrinsics_file", {{"path", "calib/ros.yaml"}, {"format", "yaml"}}}},
                dir + "/bad.json", "/cameras/0/intrinsics_file/format", "unknown intrinsics file format 'yaml'");
  require_error({{"name", "c"}, {"intrinsics_file", {{"path", "calib/camchain.yaml"}, {"format", "kalibr"}}}},
                dir + "/bad.json", "/cameras/0/intrinsics_file/camera", "the camera's name in the camchain");
  require_error({{"name", "c"}, {"intrinsics_file", {{"path", "calib/ros.yaml"}, {"format", "ros"}, {"camera", "x"}}}},
                dir + "/bad.json", "/cameras/0/intrinsics_file/camera", "picks a camera of a Kalibr camchain");
  // Problems inside the referenced file name that file, and where it was referenced.
  require_error({{"name", "c"}, {"intrinsics_file", {{"path", "calib/nope.yaml"}, {"format", "ros"}}}},
                dir + "/calib/nope.yaml", "",
                "file does not exist (intrinsics_file of " + dir + "/bad.json at /cameras/0/intrinsics_file)");
  require_error({{"name", "c"},
                 {"intrinsics_file", {{"path", "calib/camchain.yaml"}, {"format", "kalibr"}, {"camera", "cam7"}}}},
                dir + "/calib/camchain.yaml", "", "no camera 'cam7'");
}

}  // namespace
}  // namespace handeye
