// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The check every bad-input test of a loader makes.

#include <catch2/catch.hpp>
#include <string>

#include "handeye/core/error.h"

namespace handeye::test {

/// Runs `load` (which reads `file`) and requires an InputError at
/// `json_path` whose message starts "<file>: at <json_path>: " and says
/// `expected`.
template <typename Load>
void RequireInputErrorAt(const std::string& file, const std::string& json_path, const std::string& expected,
                         Load&& load) {
  try {
    load();
  } catch (const InputError& e) {
    CHECK(e.file() == file);
    CHECK(e.json_path() == json_path);
    CHECK_THAT(e.what(), Catch::Matchers::Contains(file + ": at " + json_path + ": "));
    CHECK_THAT(e.what(), Catch::Matchers::Contains(expected));
    return;
  }
  FAIL(file + " was accepted; expected an error at " + json_path + ": " + expected);
}

}  // namespace handeye::test
