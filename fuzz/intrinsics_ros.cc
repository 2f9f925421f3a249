// SPDX-License-Identifier: GPL-2.0-or-later
// ReadIntrinsicsFile, format ros: a ROS camera_info file or message.
#include "fuzz_support.h"
#include "handeye/io/intrinsics_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = handeye::fuzz::InputFile("intrinsics_ros.yaml", data, size);
  handeye::fuzz::ExpectInputErrorsOnly(
      [&] { handeye::ReadIntrinsicsFile(path, handeye::IntrinsicsFileFormat::kRos, ""); });
  return 0;
}
