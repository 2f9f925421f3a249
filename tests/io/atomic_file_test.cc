// SPDX-License-Identifier: GPL-2.0-or-later
// Atomic writes leave no temporary file behind when they fail; a folder is
// replaced whole or not at all; the temporaries in flight are known and
// removed on request (what the program does on SIGINT/SIGTERM).
#include "handeye/io/atomic_file.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <stdexcept>

#include "handeye/core/error.h"
#include "support/test_support.h"

using namespace handeye;
namespace fs = std::filesystem;

namespace {

std::size_t EntriesIn(const std::string& dir) {
  return static_cast<std::size_t>(
      std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

}  // namespace

TEST_CASE("a failed atomic write leaves no temporary file", "[io][atomic]") {
  const std::string dir = test::TempDir("atomic_write");
  // The rename cannot replace a folder that holds a file.
  test::WriteText(dir + "/taken/file.txt", "x");
  CHECK_THROWS_AS(WriteFileAtomically(dir + "/taken", "content"), InputError);
  CHECK(EntriesIn(dir) == 1);
  WriteFileAtomically(dir + "/ok.json", "{}");
  CHECK(test::ReadText(dir + "/ok.json") == "{}");
  CHECK(EntriesIn(dir) == 2);
}

TEST_CASE("a folder is replaced whole, or left as it was when the writing fails", "[io][atomic]") {
  const std::string dir = test::TempDir("atomic_folder");
  const std::string report = dir + "/report";
  ReplaceFolderAtomically(report, [](const std::string& staging) {
    test::WriteText(staging + "/index.html", "one");
    test::WriteText(staging + "/overlays/a.png", "a");
  });
  CHECK(test::ReadText(report + "/index.html") == "one");
  ReplaceFolderAtomically(
      report, [](const std::string& staging) { test::WriteText(staging + "/index.html", "two"); });
  CHECK(test::ReadText(report + "/index.html") == "two");
  CHECK_FALSE(fs::exists(report + "/overlays"));  // nothing of the old folder stays
  CHECK(EntriesIn(dir) == 1);

  CHECK_THROWS_AS(ReplaceFolderAtomically(report,
                                          [](const std::string& staging) {
                                            test::WriteText(staging + "/index.html", "three");
                                            throw std::runtime_error("drawing failed");
                                          }),
                  std::runtime_error);
  CHECK(test::ReadText(report + "/index.html") == "two");
  CHECK(EntriesIn(dir) == 1);
}

// Last in this file: after RemoveTemporariesInFlight the process is taken to
// be ending, and no folder is swapped in any more.
TEST_CASE("the temporaries in flight are removed on request", "[io][atomic]") {
  const std::string dir = test::TempDir("atomic_in_flight");
  const std::string file = TemporarySibling(dir + "/result.json");
  const std::string folder = TemporarySibling(dir + "/report");
  CHECK(fs::path(file).parent_path() == fs::path(dir));
  CHECK(fs::path(file).filename().string().rfind(".result.json.tmp", 0) == 0);
  test::WriteText(file, "half");
  test::WriteText(folder + "/overlays/a.png", "half");
  test::WriteText(dir + "/kept.json", "{}");
  {
    const TemporaryInFlight file_in_flight(file), folder_in_flight(folder);
    RemoveTemporariesInFlight();
  }
  CHECK_FALSE(fs::exists(file));
  CHECK_FALSE(fs::exists(folder));
  CHECK(fs::exists(dir + "/kept.json"));
  // Once removed, a folder is no longer swapped in: the interrupted program
  // keeps the old one.
  CHECK_THROWS_AS(ReplaceFolderAtomically(dir + "/report", [](const std::string&) {}), InputError);
  CHECK_FALSE(fs::exists(dir + "/report"));
}
