// SPDX-License-Identifier: GPL-2.0-or-later
// handeye: multi-camera hand-eye calibration. Exit codes (SPEC §7):
// 0 success, 2 bad input, 3 the calibration could not be solved.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/io/image.h"

namespace handeye::tools {

std::function<void(std::size_t, std::size_t)> ProgressLine(const std::string& what) {
  if (!isatty(fileno(stderr))) return {};
  return [what](std::size_t done, std::size_t total) {
    std::fprintf(stderr, "\r%s %zu/%zu", what.c_str(), done, total);
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  };
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

}  // namespace handeye::tools

int main(int argc, char** argv) {
  // Detection and the report go through thousands of multi-MB images.
  handeye::ReuseFreedImageMemory();
  CLI::App app{"handeye: calibrates a network of cameras against an industrial robot"};
  app.require_subcommand(1);
  handeye::tools::AddRecordedSubcommands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
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
