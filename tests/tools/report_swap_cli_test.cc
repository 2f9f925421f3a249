// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye report` builds the new report beside the old one and swaps it in
// whole: no overlay of an earlier run stays, a failed or interrupted run
// leaves the old report as it was, and no temporary file or folder survives.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "projected_cell.h"
#include "support/test_support.h"

using namespace handeye;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

// Names in `dir` that a write in flight uses (".NAME.tmp...").
std::vector<std::string> Temporaries(const std::string& dir) {
  std::vector<std::string> found;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.path().filename().string().find(".tmp") != std::string::npos)
      found.push_back(entry.path().string());
  return found;
}

}  // namespace

TEST_CASE("report replaces an earlier report whole and refuses a folder that is not one",
          "[cli][report]") {
  const std::string dir = test::TempDir("report_swap_cli");
  test::CalibratedSmallCell(dir, 6);
  const std::string report =
      "report " + dir + "/obs.json " + dir + "/result.json -o " + dir + "/rep -q";
  std::string out;
  REQUIRE(test::RunHandeye(report, &out) == 0);
  // An earlier run's overlays of a camera this result does not have.
  test::WriteText(dir + "/rep/overlays/old_camera/0001.png", "stale");
  REQUIRE(test::RunHandeye(report, &out) == 0);
  CHECK_FALSE(fs::exists(dir + "/rep/overlays/old_camera"));
  CHECK(fs::exists(dir + "/rep/index.html"));
  CHECK_THAT(out, Contains(dir + "/rep/index.html"));
  CHECK(Temporaries(dir).empty());

  // A folder of other things is not replaced (its files would be lost).
  test::WriteText(dir + "/notes/todo.txt", "keep me");
  CHECK(test::RunHandeye("report " + dir + "/obs.json " + dir + "/result.json -o " + dir + "/notes",
                         &out) == 2);
  CHECK_THAT(out, Contains("not an earlier report"));
  CHECK(test::ReadText(dir + "/notes/todo.txt") == "keep me");

  // A report that fails half way (the dataset lists images that are not
  // there) leaves the old report as it was and nothing temporary.
  nlohmann::json dataset = nlohmann::json::parse(test::ReadText(dir + "/obs.json"));
  dataset["format"] = "handeye-dataset/1";
  dataset.erase("observations");
  for (auto& pose : dataset["poses"])
    pose["images"] = {{"cam0", "missing/" + pose["id"].get<std::string>() + ".png"}};
  test::WriteText(dir + "/images.json", dataset.dump());
  const std::string index_before = test::ReadText(dir + "/rep/index.html");
  CHECK(test::RunHandeye("report " + dir + "/images.json " + dir + "/result.json --observations " +
                             dir + "/obs.json -o " + dir + "/rep",
                         &out) == 2);
  CHECK_THAT(out, Contains("missing"));
  CHECK(test::ReadText(dir + "/rep/index.html") == index_before);
  CHECK(Temporaries(dir).empty());
}

TEST_CASE("a report killed while it writes leaves the old report and no temporary files",
          "[cli][report]") {
  const std::string dir = test::TempDir("report_kill_cli");
  test::CalibratedSmallCell(dir, 20);
  std::string out;
  const std::string rep = dir + "/rep";
  REQUIRE(test::RunHandeye("report " + dir + "/obs.json " + dir + "/result.json -o " + rep + " -q",
                           &out) == 0);
  const std::string index_before = test::ReadText(rep + "/index.html");
  const std::size_t files_before =
      std::distance(fs::recursive_directory_iterator(rep), fs::recursive_directory_iterator());

  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    const std::string program = test::HandeyeBinary();
    execl(program.c_str(), program.c_str(), "report", (dir + "/obs.json").c_str(),
          (dir + "/result.json").c_str(), "-o", rep.c_str(), "--threads", "1",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  // Killed once the new report is being written beside the old one.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  bool writing = false;
  while (!writing && std::chrono::steady_clock::now() < deadline) {
    for (const auto& entry : fs::recursive_directory_iterator(dir))
      writing = writing || (entry.path().extension() == ".png" &&
                            entry.path().string().find(".rep.tmp") != std::string::npos);
    if (!writing) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  REQUIRE(writing);
  kill(child, SIGTERM);
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  CHECK(WIFSIGNALED(status));
  CHECK(WTERMSIG(status) == SIGTERM);
  CHECK(Temporaries(dir).empty());
  CHECK(test::ReadText(rep + "/index.html") == index_before);
  CHECK(std::distance(fs::recursive_directory_iterator(rep), fs::recursive_directory_iterator()) ==
        static_cast<std::ptrdiff_t>(files_before));
}
