// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Each subcommand lives in its own file and registers itself on the app.

#include <CLI/CLI.hpp>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "handeye/core/warning.h"

namespace handeye::tools {

/// Adds one subcommand to the app. Its callback throws InputError /
/// SolveError; main() maps them to exit codes 2 / 3.
using AddSubcommandFn = void (*)(CLI::App& app);

/// Records a subcommand; `order` places it in `handeye --help`. Each
/// subcommand file registers itself with HANDEYE_SUBCOMMAND, so adding a
/// subcommand is adding one file.
bool RecordSubcommand(int order, AddSubcommandFn add);
/// Adds every recorded subcommand to `app`, in order.
void AddRecordedSubcommands(CLI::App& app);

#define HANDEYE_SUBCOMMAND(order, fn) \
  [[maybe_unused]] static const bool handeye_subcommand_##fn = ::handeye::tools::RecordSubcommand(order, fn)

/// A progress printer for stderr: one line redrawn in place with the items
/// done / total, the rate and the time left, when stderr is a terminal and
/// `quiet` is false; prints nothing otherwise (logs and pipes get no
/// carriage returns).
std::function<void(std::size_t, std::size_t)> ProgressLine(const std::string& what, bool quiet);

/// Adds `--quiet` (no progress line) to a subcommand.
void AddQuietFlag(CLI::App* cmd, bool* quiet);

/// Thrown by a subcommand that finished its work but must end with a
/// non-zero status that is not an error (`check`: 4, a camera moved).
struct ExitStatus {
  int code = 0;
};

/// Makes SIGINT, SIGTERM and SIGHUP remove the temporary files and folders
/// in flight (io/atomic_file.h) before the program ends with that signal.
/// Call first in main(), before any thread starts.
void RemoveTemporariesOnInterrupt();

/// When an interrupt is being handled, waits for it to end the program
/// (called before main() returns, so that the exit status is the signal's).
void EndIfInterrupted();

/// Prints each warning on stderr as "warning: ...".
void PrintWarnings(const std::vector<std::string>& warnings);
void PrintWarnings(const std::vector<Warning>& warnings);

}  // namespace handeye::tools
