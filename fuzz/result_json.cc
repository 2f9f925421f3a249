// SPDX-License-Identifier: GPL-2.0-or-later
// LoadResult: handeye-result/1 (read by report, evaluate, export and check).
#include "fuzz_support.h"
#include "handeye/io/result_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = handeye::fuzz::InputFile("result.json", data, size);
  handeye::fuzz::ExpectInputErrorsOnly([&] { handeye::LoadResult(path); });
  return 0;
}
