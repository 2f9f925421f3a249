// SPDX-License-Identifier: GPL-2.0-or-later
// LoadDataset: handeye-dataset/1 and handeye-observations/1 (told apart by
// `format`), with their targets, cameras, poses and observations.
#include "fuzz_support.h"
#include "handeye/io/dataset_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = handeye::fuzz::InputFile("dataset.json", data, size);
  handeye::fuzz::ExpectInputErrorsOnly([&] { handeye::LoadDataset(path); });
  return 0;
}
