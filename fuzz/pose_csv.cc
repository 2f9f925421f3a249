// SPDX-License-Identifier: GPL-2.0-or-later
// ReadPoseCsv: the robot pose list of `handeye import-poses`.
#include "fuzz_support.h"
#include "handeye/io/pose_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = handeye::fuzz::InputFile("poses.csv", data, size);
  handeye::fuzz::ExpectInputErrorsOnly(
      [&] { handeye::ReadPoseCsv(path, handeye::LengthUnit::kMillimetre, false); });
  return 0;
}
