// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// What every fuzz target shares. handeye's loaders read files, so each
// input is written to a file in a folder private to the fuzzing process
// and the loader reads it from there. A loader may refuse an input only
// with handeye::InputError (exit code 2 in the tools); any other exception
// would be an "internal error" (exit 1) for a user and is a finding here.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>
#include <typeinfo>

#include "handeye/core/error.h"

namespace handeye::fuzz {

/// A folder for this process's files (created once, under $TMPDIR or /tmp).
inline const std::string& WorkDir() {
  static const std::string dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/handeye-fuzz-XXXXXX";
    if (!mkdtemp(pattern.data())) {
      std::perror("mkdtemp");
      std::abort();
    }
    return pattern;
  }();
  return dir;
}

/// Writes `size` bytes to `path`, replacing what was there.
inline void WriteFile(const std::string& path, const std::uint8_t* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!out) {
    std::perror(path.c_str());
    std::abort();
  }
}

/// The input as WorkDir()/name.
inline std::string InputFile(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = WorkDir() + "/" + name;
  WriteFile(path, data, size);
  return path;
}

/// Runs `load`: returning or throwing InputError are both fine; any other
/// exception aborts, which libFuzzer records as a crash with the input.
template <class Load>
void ExpectInputErrorsOnly(Load&& load) {
  try {
    load();
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "finding: %s instead of handeye::InputError: %s\n", typeid(e).name(), e.what());
    std::abort();
  }
}

}  // namespace handeye::fuzz
