// SPDX-License-Identifier: GPL-2.0-or-later
#include "cli_numbers.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <thread>

#include "handeye/core/error.h"

namespace handeye::tools {
namespace {

std::string Refuse(const std::string& expected, const std::string& text) {
  return "expected " + expected + ", got " + (text.empty() ? std::string("nothing") : text);
}

// strtoll / strtoull / strtod accept leading blanks and stop early; an option
// value must be the number and nothing else.
bool WholeText(const std::string& text, const char* end) {
  return !text.empty() && !std::isspace(static_cast<unsigned char>(text[0])) &&
         end == text.c_str() + text.size();
}

}  // namespace

CLI::Validator IntegerIn(long long min_value, long long max_value, const std::string& expected) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long long value = std::strtoll(text.c_str(), &end, 10);
        if (!WholeText(text, end) || errno == ERANGE || value < min_value || value > max_value)
          return Refuse(expected, text);
        return "";
      },
      "");
}

CLI::Validator UnsignedInteger(const std::string& expected) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        // strtoull would wrap "-1" around to 2^64 - 1.
        if (text.find('-') != std::string::npos) return Refuse(expected, text);
        std::strtoull(text.c_str(), &end, 10);
        if (!WholeText(text, end) || errno == ERANGE) return Refuse(expected, text);
        return "";
      },
      "");
}

CLI::Validator NumberIn(double min_value, double max_value, bool exclusive_min,
                        const std::string& expected) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        const bool above_min = exclusive_min ? value > min_value : value >= min_value;
        if (!WholeText(text, end) || !std::isfinite(value) || !above_min || value > max_value)
          return Refuse(expected, text);
        return "";
      },
      "");
}

CLI::Validator ThreadCount() {
  // Each thread holds an image or a solver's workspace: far more threads
  // than cores only cost memory (100000 threads: 844 MB instead of 240).
  const long long cores = std::max(1u, std::thread::hardware_concurrency());
  const long long most = std::min<long long>(kMaxThreads, kMaxThreadsPerCore * cores);
  return IntegerIn(0, most,
                   "0 (all cores) or a positive count up to " + std::to_string(most) + " (" +
                       std::to_string(kMaxThreadsPerCore) + " per core, at most " +
                       std::to_string(kMaxThreads) + ")");
}

CLI::Validator PositiveNumber(const std::string& expected) {
  return NumberIn(0, std::numeric_limits<double>::max(), true, expected);
}

CLI::Validator NonNegativeNumber(const std::string& expected) {
  return NumberIn(0, std::numeric_limits<double>::max(), false, expected);
}

std::pair<int, int> ParseTwoCounts(const std::string& option, const std::string& text,
                                   const std::string& what) {
  int a = 0, b = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &a, &x, &b, &extra) != 3 || (x != 'x' && x != 'X') ||
      a <= 0 || b <= 0)
    throw InputError("", option, "expected " + what + ", got '" + text + "'");
  return {a, b};
}

}  // namespace handeye::tools
