// SPDX-License-Identifier: GPL-2.0-or-later
// LoadGroundTruth: ground_truth.json (what `handeye evaluate` reads).
#include "fuzz_support.h"
#include "handeye/io/dataset_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = handeye::fuzz::InputFile("ground_truth.json", data, size);
  handeye::fuzz::ExpectInputErrorsOnly([&] { handeye::LoadGroundTruth(path); });
  return 0;
}
