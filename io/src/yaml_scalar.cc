// SPDX-License-Identifier: GPL-2.0-or-later
#include "yaml_scalar.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace handeye::internal {
namespace {

bool IsDigit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

// Skips digits from `at`; returns how many there were.
std::size_t SkipDigits(const std::string& s, std::size_t* at) {
  const std::size_t start = *at;
  while (*at < s.size() && IsDigit(s[*at])) ++*at;
  return *at - start;
}

enum class NumberKind { kNone, kInteger, kReal };

NumberKind Classify(const std::string& s) {
  std::size_t at = 0;
  if (at < s.size() && (s[at] == '-' || s[at] == '+')) ++at;
  const std::size_t whole = SkipDigits(s, &at);
  bool real = false;
  if (at < s.size() && s[at] == '.') {
    ++at;
    const std::size_t fraction = SkipDigits(s, &at);
    if (whole == 0 && fraction == 0) return NumberKind::kNone;
    real = true;
  } else if (whole == 0) {
    return NumberKind::kNone;
  }
  if (at < s.size() && (s[at] == 'e' || s[at] == 'E')) {
    ++at;
    if (at < s.size() && (s[at] == '-' || s[at] == '+')) ++at;
    if (SkipDigits(s, &at) == 0) return NumberKind::kNone;
    real = true;
  }
  if (at != s.size()) return NumberKind::kNone;
  return real ? NumberKind::kReal : NumberKind::kInteger;
}

}  // namespace

nlohmann::json PlainYamlScalar(const std::string& text) {
  if (text.empty() || text == "~" || text == "null" || text == "Null" || text == "NULL") return nullptr;
  if (text == "true" || text == "True" || text == "TRUE") return true;
  if (text == "false" || text == "False" || text == "FALSE") return false;
  const NumberKind kind = Classify(text);
  if (kind == NumberKind::kInteger) {
    errno = 0;
    const long long value = std::strtoll(text.c_str(), nullptr, 10);
    if (errno == 0) return static_cast<std::int64_t>(value);
  }
  if (kind != NumberKind::kNone) {
    // An integer too long for 64 bits is still a number.
    errno = 0;
    const double value = std::strtod(text.c_str(), nullptr);
    if (errno == 0 && std::isfinite(value)) return value;
  }
  return text;
}

}  // namespace handeye::internal
