// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Each subcommand lives in its own file and registers itself on the app.

#include <CLI/CLI.hpp>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace handeye::tools {

/// Adds the subcommand to `app`. Its callback throws InputError / SolveError;
/// main() maps them to exit codes 2 / 3.
void RegisterDetect(CLI::App& app);
void RegisterSimulate(CLI::App& app);
void RegisterImportMetric(CLI::App& app);
void RegisterCalibrate(CLI::App& app);
void RegisterEvaluate(CLI::App& app);

/// A progress printer for stderr: redraws one line when stderr is a terminal,
/// prints nothing otherwise.
std::function<void(std::size_t, std::size_t)> ProgressLine(const std::string& what);

/// Prints each warning on stderr as "warning: ...".
void PrintWarnings(const std::vector<std::string>& warnings);

}  // namespace handeye::tools
