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
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <typeinfo>

#include "handeye/core/error.h"

namespace handeye::fuzz {

/// A folder for this process's files, created once and removed at exit:
/// under $TMPDIR if set, else in /dev/shm, else in /tmp. Memory, not disk:
/// on a disk-backed /tmp the write-back of one small file per input took
/// nine tenths of the time (perf: ext4 write-back and page clearing in the
/// kernel; pose_csv ran 500 inputs/s from /tmp and 4,700 from /dev/shm).
inline const std::string& WorkDir() {
  static const std::string dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::string parent = tmp && *tmp ? tmp : "/tmp";
    if (!(tmp && *tmp) && std::filesystem::is_directory("/dev/shm")) parent = "/dev/shm";
    std::string pattern = parent + "/handeye-fuzz-XXXXXX";
    if (!mkdtemp(pattern.data())) {
      std::perror("mkdtemp");
      std::abort();
    }
    return pattern;
  }();
  // libFuzzer ends a run with exit(), so the folder goes; after a crash it
  // stays, with the input that caused it.
  static const bool cleanup_registered = [] {
    return std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }) == 0;
  }();
  (void)cleanup_registered;
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
