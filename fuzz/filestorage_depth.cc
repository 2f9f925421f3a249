// SPDX-License-Identifier: GPL-2.0-or-later
// The nesting guards in front of OpenCV's FileStorage parsers
// (io/src/filestorage_depth.h): any text must open without a crash (OpenCV
// parses on a stack that holds its recursion), and a text that opens must
// not be deeper than kMaxFileStorageDepth, counted on the tree OpenCV built.
// A crash, or an accepted tree deeper than the limit, is a finding. The
// quick first measure is not held to the tree here: it only spares OpenCV
// the deep texts it recognises.
#include "../io/src/filestorage_depth.h"

#include <cstdio>
#include <cstdlib>

#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  handeye::fuzz::ExpectInputErrorsOnly([&] {
    const cv::FileStorage fs = handeye::internal::OpenFileStorageText(text, "fuzz.yaml");
    const int real = handeye::internal::FileStorageTreeDepth(fs.root());
    if (real > handeye::internal::kMaxFileStorageDepth) {
      std::fprintf(stderr, "finding: a tree %d deep was accepted; the limit is %d\n", real,
                   handeye::internal::kMaxFileStorageDepth);
      std::abort();
    }
  });
  return 0;
}
