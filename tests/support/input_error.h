// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The checks every bad-input test of a loader or a target makes.

#include <catch2/catch.hpp>
#include <string>
#include <utility>

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

/// The JSON path and the `expected` text of the InputError that `call`
/// throws (a failed test when it throws none), to compare whole.
template <typename Call>
std::pair<std::string, std::string> InputErrorOf(Call&& call) {
  try {
    call();
  } catch (const InputError& e) {
    return {e.json_path(), e.expected()};
  }
  FAIL("no InputError");
  return {};
}

}  // namespace handeye::test
