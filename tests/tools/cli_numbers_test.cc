// SPDX-License-Identifier: GPL-2.0-or-later
// Every numeric option of every subcommand: a bad value exits with 2 and a
// message in words ("--threads: expected 0 (all cores) or a positive count,
// got -1"), never CLI11's range text with its 309-digit bound.
#include <algorithm>
#include <catch2/catch.hpp>
#include <string>
#include <thread>

#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;

struct BadOption {
  const char* command;   // subcommand with its positional arguments ({in}, {sim})
  const char* option;
  const char* value;
  const char* expected;  // what the message says is wanted
};

TEST_CASE("Numeric options say what they expect", "[tools][cli][bad]") {
  const std::string dir = test::TempDir("cli_numbers");
  const std::string in = dir + "/in.json", out = " -o " + dir + "/out";
  // --threads: at most 64 per core and 1024 in all (tools/cli_numbers.h).
  const long long most_threads = std::min(1024LL, 64LL * std::max(1u, std::thread::hardware_concurrency()));
  const std::string threads_text = "0 (all cores) or a positive count up to " + std::to_string(most_threads) +
                                   " (64 per core, at most 1024)";
  const char* threads = threads_text.c_str();
  const std::string too_many_text = std::to_string(most_threads + 1);
  const BadOption cases[] = {
      {"detect {in}", "--threads", "-1", threads},
      {"detect {in}", "--threads", "1.5", threads},
      {"detect {in}", "--threads", "100000", threads},
      {"detect {in}", "--threads", too_many_text.c_str(), threads},
      {"calibrate {in}", "--threads", "-1", threads},
      {"calibrate {in}", "--cauchy-scale", "-1", "0 (from the residuals) or a positive scale in pixels"},
      {"calibrate {in}", "--robot-sigma-mm", "-0.5", "a non-negative sigma in mm"},
      {"calibrate {in}", "--cauchy-scale", "nan", "0 (from the residuals) or a positive scale in pixels"},
      {"report {in} {in}", "--threads", "x", threads},
      {"simulate {sim}", "--threads", "-2", threads},
      {"simulate {sim}", "--cameras", "0", "between 1 and 64 cameras"},
      {"simulate {sim}", "--cameras", "65", "between 1 and 64 cameras"},
      {"simulate {sim}", "--poses", "-5", "between 1 and 100000 poses"},
      {"simulate {sim}", "--seed", "-1", "a whole number from 0 to 2^64 - 1"},
      {"simulate {sim}", "--seed", "99999999999999999999", "a whole number from 0 to 2^64 - 1"},
      {"simulate {sim}", "--pose-noise-mm", "-0.1", "a non-negative robot translation noise sigma in mm"},
      {"simulate {sim}", "--pose-noise-deg", "inf", "a non-negative robot rotation noise sigma in degrees"},
      {"simulate {sim}", "--blur", "-1", "a non-negative blur sigma in pixels"},
      {"simulate {sim}", "--noise", "lots", "a non-negative noise sigma in grey levels"},
      {"simulate {sim}", "--square", "-0.04", "a positive size in metres"},
      {"simulate {sim}", "--marker", "0", "a positive size in metres"},
      {"target", "--tag-size", "0", "a positive size in metres"},
      {"target", "--tag-spacing", "-1", "a positive ratio of gap to tag size"},
      {"target", "--border-bits", "3", "1 or 2 border bits"},
      {"target", "--dpi", "5", "a resolution between 10 and 2400 dots per inch"},
  };
  for (const BadOption& c : cases) {
    std::string command = c.command;
    for (const auto& [name, path] : {std::pair<std::string, std::string>{"{in}", in}, {"{sim}", dir + "/sim"}})
      for (std::size_t at; (at = command.find(name)) != std::string::npos;)
        command.replace(at, name.size(), "'" + path + "'");
    const std::string args = command + out + " " + c.option + " " + c.value;
    std::string output;
    INFO(args);
    CHECK(test::RunHandeye(args, &output) == 2);
    CHECK_THAT(output, Contains(std::string(c.option) + ": expected " + c.expected + ", got " + c.value));
    CHECK_THAT(output, !Contains("not in range"));
  }
}

}  // namespace
}  // namespace handeye
