// SPDX-License-Identifier: GPL-2.0-or-later
// ReadPoseCsv with every rotation form (quaternion, rotation vector, KUKA
// A B C, roll pitch yaw; from the header, or named as --rotation does by the
// input's length) and the reach check import-poses makes on what it read.
#include "fuzz_support.h"
#include "handeye/io/pose_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = handeye::fuzz::InputFile("poses.csv", data, size);
  handeye::PoseListOptions options;
  options.unit = size % 2 ? handeye::LengthUnit::kMillimetre : handeye::LengthUnit::kMetre;
  options.reorthonormalise = size % 3 == 0;
  const handeye::CsvRotation rotations[] = {
      handeye::CsvRotation::kQuaternion, handeye::CsvRotation::kRotationVector,
      handeye::CsvRotation::kKukaAbc, handeye::CsvRotation::kRpy};
  if (size % 5 < 4) options.rotation = rotations[size % 5];
  for (int pass = 0; pass < 2; ++pass) {
    handeye::fuzz::ExpectInputErrorsOnly([&] {
      const auto rows = handeye::ReadPoseCsv(path, options);
      handeye::RequirePlausibleReach(rows, path, options.unit, "--translation-unit");
    });
    options.rotation.reset();  // and from the header
  }
  return 0;
}
