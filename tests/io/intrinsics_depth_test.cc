// SPDX-License-Identifier: GPL-2.0-or-later
// OpenCV 4.6's FileStorage parsers recurse once per nesting level with no
// limit: a camera_matrix nested 50 000 deep (100 KB) overflowed the stack
// (exit 139). The loader measures the nesting before OpenCV reads the text.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "../../io/src/filestorage_depth.h"
#include "handeye/core/error.h"
#include "handeye/io/intrinsics_files.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;

constexpr int kDeep = 50000;

std::string Repeat(const std::string& piece, int n) {
  std::string out;
  out.reserve(piece.size() * n);
  for (int k = 0; k < n; ++k) out += piece;
  return out;
}

const char kDistortion[] =
    "distortion_coefficients: !!opencv-matrix\n  rows: 1\n  cols: 4\n  dt: d\n"
    "  data: [0.1, -0.01, 0, 0]\n";

// The four spellings of a camera_matrix nested `depth` levels below the root.
std::string YamlFlow(int depth) {
  return "%YAML:1.0\ncamera_matrix: " + Repeat("[", depth) + "1" + Repeat("]", depth) + "\n" +
         kDistortion;
}
std::string YamlBlock(int depth) {
  return "camera_matrix:\n  " + Repeat("- ", depth) + "1\n" + kDistortion;
}
std::string Json(int depth) {
  return "{\"camera_matrix\": " + Repeat("{\"a\": [", depth) + "1" + Repeat("]}", depth) + "}";
}
std::string Xml(int depth) {
  return "<?xml version=\"1.0\"?>\n<opencv_storage>\n<camera_matrix>" + Repeat("<_>", depth) + "1" +
         Repeat("</_>", depth) + "</camera_matrix>\n</opencv_storage>\n";
}

void RequireDepthError(const std::string& path) {
  try {
    ReadIntrinsicsFile(path, IntrinsicsFileFormat::kOpenCv, "");
  } catch (const InputError& e) {
    CHECK(e.file() == path);
    CHECK_THAT(e.what(), Contains("nested more than 64 levels deep"));
    return;
  }
  FAIL(path + " was accepted; expected an error about its nesting");
}

TEST_CASE(
    "OpenCV FileStorage: text nested deeper than 64 levels is refused before OpenCV parses it",
    "[io][intrinsics][bad]") {
  const std::string dir = test::TempDir("intrinsics_opencv_depth");
  for (const auto& [name, text] :
       {std::pair<std::string, std::string>{"flow.yml", YamlFlow(kDeep)},
        {"block.yml", YamlBlock(kDeep)},
        {"deep.json", Json(kDeep / 2)},
        // 50 000 levels were not enough to crash OpenCV's JSON parser; 10^6
        // were (the text is 1 MB at most now).
        {"deep_arrays.json",
         "{\"camera_matrix\": " + Repeat("[", 500000) + "1" + Repeat("]", 500000) + "}"},
        {"deep.xml", Xml(kDeep)},
        {"just_over.yml", YamlFlow(64)},
        {"just_over_block.yml", YamlBlock(64)},
        {"just_over.json", Json(32)},
        {"just_over.xml", Xml(64)}}) {
    INFO(name);
    test::WriteText(dir + "/" + name, text);
    RequireDepthError(dir + "/" + name);
  }
  // A few levels are not refused for their depth: OpenCV reads them, and
  // camera_matrix fails as the wrong kind of value.
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"shallow.yml", YamlFlow(10)},
                                   {"shallow_block.yml", YamlBlock(10)},
                                   {"shallow.json", Json(10)},
                                   {"shallow.xml", Xml(10)}}) {
    INFO(name);
    test::WriteText(dir + "/" + name, text);
    try {
      ReadIntrinsicsFile(dir + "/" + name, IntrinsicsFileFormat::kOpenCv, "");
      FAIL("accepted");
    } catch (const InputError& e) {
      CHECK(e.json_path() == "/camera_matrix");
      CHECK_THAT(e.what(), Contains("expected an opencv-matrix"));
    }
  }
}

TEST_CASE("OpenCV parses on a stack that holds its deepest recursion, and the tree it built is measured again",
          "[io][intrinsics][bad]") {
  // The first measure can be outwitted (fuzz/run found five texts it counted
  // short); what keeps OpenCV from overflowing the stack is the thread it
  // parses on. 500 000 levels crashed it on the main thread's 8 MB.
  constexpr int kLevels = 500000;
  const std::string text = "%YAML:1.0\na: " + Repeat("[", kLevels) + "1" + Repeat("]", kLevels) + "\n";
  REQUIRE(text.size() <= internal::kMaxFileStorageTextBytes);
  const cv::FileStorage fs =
      internal::ParseFileStorageText(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  REQUIRE(fs.isOpened());
  CHECK(internal::FileStorageTreeDepth(fs.root()) == kLevels + 1);
  CHECK(internal::FileStorageTreeDepth(internal::ParseFileStorageText(
                                           "%YAML:1.0\na: 1\nb: [1, {c: [2]}]\n",
                                           cv::FileStorage::READ | cv::FileStorage::MEMORY)
                                           .root()) == 4);
}

TEST_CASE("An OpenCV intrinsics file over a megabyte is refused before it is parsed", "[io][intrinsics][bad]") {
  const std::string dir = test::TempDir("intrinsics_opencv_size");
  test::WriteText(dir + "/big.yml", "%YAML:1.0\ncomment: \"" + std::string(internal::kMaxFileStorageTextBytes, 'x') + "\"\n");
  try {
    ReadIntrinsicsFile(dir + "/big.yml", IntrinsicsFileFormat::kOpenCv, "");
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.file() == dir + "/big.yml");
    CHECK_THAT(e.what(), Contains("at most 1 MB is read"));
  }
}

int TreeDepth(const cv::FileNode& node) { return internal::FileStorageTreeDepth(node); }

TEST_CASE("The nesting guard never measures less than the tree OpenCV builds",
          "[io][intrinsics][bad]") {
  using internal::FileStorageSyntax;
  // The first three fuzz/run found: OpenCV reads "--" as two sequences, a
  // second tag as text (here a key) and a '%' line after the first key as a
  // key, where the guard counted none of them.
  const auto finding = [](const char* name) {
    return test::ReadText(
        (std::filesystem::path(HANDEYE_TEST_SOURCE_DIR "/io") / "fuzz_findings" / name).string());
  };
  for (const auto& [text, syntax] :
       {std::pair<std::string, FileStorageSyntax>{
            "%YAML:1.0\n" + finding("opencv_yaml_dash_sequences.yaml"), FileStorageSyntax::kYaml},
        {"%YAML:1.0\n" + finding("opencv_yaml_second_tag.yaml"), FileStorageSyntax::kYaml},
        {"%YAML:1.0\n" + finding("opencv_yaml_percent_key.yaml"), FileStorageSyntax::kYaml},
        {"%YAML:1.0\na: 1\n%b: [[[1]]]\n", FileStorageSyntax::kYaml},
        {"%YAML:1.0\n" + finding("opencv_yaml_percent_after_start.yaml"), FileStorageSyntax::kYaml},
        {"%YAML:1.0\n---\n%b: [[[1]]]\n", FileStorageSyntax::kYaml},
        {"%YAML:1.0\na: !!x !!y: [[1]]\nb: [!!u !!v, [[2]]]\n", FileStorageSyntax::kYaml},
        {"%YAML:1.0\na: --x\nb: -y\nc: -1\n", FileStorageSyntax::kYaml},
        {"%YAML:1.0\na:\n  -\n    - [1, {b: c}]\n  - d: e: f\n", FileStorageSyntax::kYaml},
        {"%YAML:1.0\na: {'k]': ['x]', \"y]\"], l}: [[2]]\n", FileStorageSyntax::kYaml},
        {"{\"a\": [\"]]\", [{\"b\": [1]}]]}", FileStorageSyntax::kJson},
        {"<?xml version=\"1.0\"?>\n<opencv_storage><a><_>\"</_>\" 1</_></a></opencv_storage>\n",
         FileStorageSyntax::kXml}}) {
    INFO(text);
    int real = -1;
    try {
      real = TreeDepth(internal::OpenFileStorageText(text, "t").root());
    } catch (const InputError&) {
      continue;  // refused before or by OpenCV: nothing to compare
    }
    CHECK(internal::FileStorageNestingDepth(text, syntax, 1 << 30) >= real);
  }
}

}  // namespace
}  // namespace handeye
