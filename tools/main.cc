// SPDX-License-Identifier: GPL-2.0-or-later
// handeye: multi-camera hand-eye calibration. Exit codes (SPEC §7):
// 0 success, 2 bad input, 3 the calibration could not be solved (or `check`
// could not tell), 4 `check` found a camera that moved.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/core/input_limits.h"
#include "handeye/io/image.h"

namespace handeye::tools {

namespace {

/// Seconds as "m:ss" (or "h:mm:ss").
std::string Duration(double seconds) {
  const long total = std::lround(std::max(0.0, seconds));
  char text[32];
  if (total >= 3600)
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", total / 3600, total / 60 % 60, total % 60);
  else
    std::snprintf(text, sizeof text, "%ld:%02ld", total / 60, total % 60);
  return text;
}

}  // namespace

std::function<void(std::size_t, std::size_t)> ProgressLine(const std::string& what, bool quiet) {
  if (quiet || !isatty(fileno(stderr))) return {};
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  // Redrawn at most 10 times a second: a thousand images a second would
  // otherwise spend more time on the terminal than on the work.
  auto last_drawn = std::make_shared<Clock::time_point>(start - std::chrono::seconds(1));
  return [what, start, last_drawn](std::size_t done, std::size_t total) {
    const Clock::time_point now = Clock::now();
    if (done < total && now - *last_drawn < std::chrono::milliseconds(100)) return;
    *last_drawn = now;
    const double elapsed = std::chrono::duration<double>(now - start).count();
    const double rate = elapsed > 0 ? done / elapsed : 0.0;
    std::string tail;
    if (done == total)
      tail = "in " + Duration(elapsed);
    else if (done > 0 && rate > 0)
      tail = "ETA " + Duration((total - done) / rate);
    // \r back to the start of the line, \033[K clears what a longer line left.
    std::fprintf(stderr, "\r%s %zu/%zu  %.1f/s  %s\033[K", what.c_str(), done, total, rate,
                 tail.c_str());
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  };
}

void AddQuietFlag(CLI::App* cmd, bool* quiet) {
  cmd->add_flag("-q,--quiet", *quiet, "no progress line on the terminal");
}

namespace {

std::vector<std::pair<int, AddSubcommandFn>>& Recorded() {
  static std::vector<std::pair<int, AddSubcommandFn>> recorded;
  return recorded;
}

}  // namespace

bool RecordSubcommand(int order, AddSubcommandFn add) {
  Recorded().emplace_back(order, add);
  return true;
}

void AddRecordedSubcommands(CLI::App& app) {
  auto recorded = Recorded();
  std::stable_sort(recorded.begin(), recorded.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [order, add] : recorded) add(app);
}

void PrintWarnings(const std::vector<std::string>& warnings) {
  for (const auto& w : warnings) std::cerr << "warning: " << w << "\n";
}

void PrintWarnings(const std::vector<Warning>& warnings) { PrintWarnings(WarningTexts(warnings)); }

}  // namespace handeye::tools

namespace {

// The input caps (docs/conventions.md, "Input limits"), for every command:
// `handeye detect d.json -o o.json --max-image-pixels 3e8`. They are the
// main command's options, taken after the subcommand's too (fallthrough), and
// set before the subcommand runs (CLI11 runs the main command's option
// callbacks before the subcommands' final callbacks).
void AddInputLimitOptions(CLI::App& app) {
  const auto positive_integer = [](const std::string& text) -> std::string {
    try {
      std::size_t used = 0;
      const double value = std::stod(text, &used);
      if (used == text.size() && value >= 1 && value <= 9007199254740992.0 && value == std::floor(value))
        return "";
    } catch (const std::exception&) {
    }
    return "expected a positive integer (3e8 is read as 300000000), got '" + text + "'";
  };
  app.add_option_function<double>(
         "--max-target-points",
         [](double points) { handeye::SetMaxTargetPoints(static_cast<std::int64_t>(points)); },
         "largest number of points one target may have (default 20000; docs/conventions.md)")
      ->check(positive_integer);
  app.add_option_function<double>(
         "--max-image-pixels",
         [](double pixels) { handeye::SetMaxImagePixels(static_cast<std::int64_t>(pixels)); },
         "largest width x height of one image (default 200000000; docs/conventions.md)")
      ->check(positive_integer);
  app.fallthrough();
}

// Parses and runs the subcommand; returns the exit code (SPEC §7).
int Run(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  } catch (const handeye::tools::ExitStatus& status) {
    return status.code;
  } catch (const handeye::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const handeye::SolveError& e) {
    std::cerr << "error: calibration failed: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  handeye::tools::RemoveTemporariesOnInterrupt();
  // Detection and the report go through thousands of multi-MB images.
  handeye::ReuseFreedImageMemory();
  CLI::App app{"handeye: calibrates a network of cameras against an industrial robot"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "handeye " HANDEYE_VERSION);
  AddInputLimitOptions(app);
  handeye::tools::AddRecordedSubcommands(app);
  const int code = Run(app, argc, argv);
  // A write that failed because an interrupt removed its folder ends with
  // the signal, as the interrupt asked, not with the write's error.
  handeye::tools::EndIfInterrupted();
  return code;
}
