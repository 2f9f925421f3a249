// SPDX-License-Identifier: GPL-2.0-or-later
// A `target` object as `--target-json` reads it: parsed, turned into a
// TargetSpec and made into a target (its geometry and detector).
#include "fuzz_support.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/json_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = handeye::fuzz::InputFile("target.json", data, size);
  handeye::fuzz::ExpectInputErrorsOnly([&] {
    const nlohmann::json root = handeye::ReadJsonFile(path);
    const auto target = handeye::MakeTarget(handeye::TargetSpecFromJson(handeye::JsonReader(&root, path)));
    handeye::MakeDetector(target);
  });
  return 0;
}
