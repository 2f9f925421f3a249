// SPDX-License-Identifier: GPL-2.0-or-later
// ReadIntrinsicsFile, format opencv: an OpenCV FileStorage file (YAML, XML or JSON).
#include "fuzz_support.h"
#include "handeye/io/intrinsics_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = handeye::fuzz::InputFile("intrinsics_opencv.yaml", data, size);
  handeye::fuzz::ExpectInputErrorsOnly(
      [&] { handeye::ReadIntrinsicsFile(path, handeye::IntrinsicsFileFormat::kOpenCv, ""); });
  return 0;
}
