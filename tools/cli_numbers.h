// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Validators for the numeric options of every subcommand. CLI11's own range
// checks print the range's bounds (for NonNegativeNumber a 309-digit number);
// these say what the option wants in words, as the rest of handeye's messages
// do: "--threads: expected 0 (all cores) or a positive count, got -1".
// A validator sees the text as given, before CLI11 converts it, so "abc" and
// "1.5" for an integer option get the same message.

#include <CLI/CLI.hpp>
#include <string>
#include <utility>

namespace handeye::tools {

/// A whole number in [min_value, max_value] (decimal digits, optional sign);
/// `expected` is what the message says the option wants.
CLI::Validator IntegerIn(long long min_value, long long max_value, const std::string& expected);

/// An unsigned 64-bit whole number (random seeds).
CLI::Validator UnsignedInteger(const std::string& expected);

/// A finite number in [min_value, max_value]; with `exclusive_min` min_value
/// itself is refused (positive sizes, scales).
CLI::Validator NumberIn(double min_value, double max_value, bool exclusive_min,
                        const std::string& expected);

/// --threads: at most this many per core, and this many in all.
constexpr long long kMaxThreadsPerCore = 64;
constexpr long long kMaxThreads = 1024;

/// The usual ones: --threads (0 = all cores, at most kMaxThreadsPerCore per
/// core and kMaxThreads) and a finite positive number.
CLI::Validator ThreadCount();
CLI::Validator PositiveNumber(const std::string& expected);
CLI::Validator NonNegativeNumber(const std::string& expected);

/// "AxB" with two positive integers ("7x4", "1920x1080"); anything else throws
/// InputError for `option`, saying it expected `what`.
std::pair<int, int> ParseTwoCounts(const std::string& option, const std::string& text,
                                   const std::string& what);

}  // namespace handeye::tools
