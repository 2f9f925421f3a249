// SPDX-License-Identifier: GPL-2.0-or-later
// The nesting guard in front of OpenCV's FileStorage parsers
// (io/src/filestorage_depth.h): text that passes the checks must open
// without a crash, and OpenCV's tree must never be deeper than the depth
// the guard measured (were it, text nested past the limit could reach
// OpenCV's unbounded recursion). A tree deeper than measured is a finding.
#include "../io/src/filestorage_depth.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "fuzz_support.h"

namespace {

int TreeDepth(const cv::FileNode& node) {
  if (!node.isMap() && !node.isSeq()) return 0;
  int deepest = 0;
  for (auto it = node.begin(); it != node.end(); ++it) deepest = std::max(deepest, TreeDepth(*it));
  return deepest + 1;
}

// The text and syntax OpenFileStorageText hands to OpenCV.
std::pair<std::string, handeye::internal::FileStorageSyntax> AsOpenCvReadsIt(std::string text) {
  using handeye::internal::FileStorageSyntax;
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  const char lead = first == std::string::npos ? '\0' : text[first];
  if (lead == '<') return {text, FileStorageSyntax::kXml};
  if (lead == '{') return {text, FileStorageSyntax::kJson};
  if (text.compare(first == std::string::npos ? 0 : first, 5, "%YAML") != 0)
    text = "%YAML:1.0\n" + text;
  return {text, FileStorageSyntax::kYaml};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  handeye::fuzz::ExpectInputErrorsOnly([&] {
    const cv::FileStorage fs = handeye::internal::OpenFileStorageText(text, "fuzz.yaml");
    const auto [read, syntax] = AsOpenCvReadsIt(text);
    const int measured = handeye::internal::FileStorageNestingDepth(read, syntax, 1 << 30);
    const int real = TreeDepth(fs.root());  // one document: the checks refuse more
    if (real > measured) {
      std::fprintf(stderr, "finding: OpenCV's tree is %d deep, the guard measured %d\n", real,
                   measured);
      std::abort();
    }
  });
  return 0;
}
