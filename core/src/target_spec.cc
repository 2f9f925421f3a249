// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/target_spec.h"

#include <cmath>

#include "handeye/core/error.h"

namespace handeye {
namespace {

const TargetValue& Require(const TargetSpec& spec, const std::string& key,
                           const std::string& expected) {
  auto it = spec.values.find(key);
  if (it == spec.values.end())
    throw InputError("", "/" + key, "missing key; expected " + expected + " for a '" + spec.type +
                                        "' target");
  return it->second;
}

double RequireNumber(const TargetSpec& spec, const std::string& key, const std::string& expected) {
  const TargetValue& v = Require(spec, key, expected);
  if (!std::holds_alternative<double>(v)) throw InputError("", "/" + key, "expected " + expected);
  const double x = std::get<double>(v);
  if (!std::isfinite(x)) throw InputError("", "/" + key, "expected " + expected + ", got NaN/Inf");
  return x;
}

}  // namespace

double TargetSpec::GetPositive(const std::string& key) const {
  const double x = RequireNumber(*this, key, "a positive number");
  if (x <= 0) throw InputError("", "/" + key, "expected a positive number");
  return x;
}

double TargetSpec::GetFraction(const std::string& key) const {
  const double x = RequireNumber(*this, key, "a number between 0 and 1");
  if (x <= 0 || x >= 1) throw InputError("", "/" + key, "expected a number between 0 and 1");
  return x;
}

int TargetSpec::GetInt(const std::string& key, int min_value) const {
  const std::string expected = "an integer >= " + std::to_string(min_value);
  const double x = RequireNumber(*this, key, expected);
  if (x != std::floor(x) || x < min_value || x > 1e6) throw InputError("", "/" + key, "expected " + expected);
  return static_cast<int>(x);
}

std::array<int, 2> TargetSpec::GetIntPair(const std::string& key, int min_value) const {
  const std::string expected = "two integers >= " + std::to_string(min_value);
  const TargetValue& v = Require(*this, key, expected);
  const auto* list = std::get_if<std::vector<double>>(&v);
  if (!list || list->size() != 2) throw InputError("", "/" + key, "expected " + expected);
  std::array<int, 2> out{};
  for (int i = 0; i < 2; ++i) {
    const double x = (*list)[i];
    if (!std::isfinite(x) || x != std::floor(x) || x < min_value || x > 1e6)
      throw InputError("", "/" + key + "/" + std::to_string(i), "expected " + expected);
    out[i] = static_cast<int>(x);
  }
  return out;
}

std::string TargetSpec::GetString(const std::string& key, const std::string& fallback) const {
  auto it = values.find(key);
  if (it == values.end()) return fallback;
  const auto* s = std::get_if<std::string>(&it->second);
  if (!s) throw InputError("", "/" + key, "expected a string");
  return *s;
}

void TargetSpec::RejectUnknownKeys(const std::vector<std::string>& known) const {
  for (const auto& [key, value] : values) {
    bool ok = false;
    for (const auto& k : known) ok = ok || k == key;
    if (!ok) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw InputError("", "/" + key,
                       "unknown key for a '" + type + "' target; expected only: type, " + list);
    }
  }
}

}  // namespace handeye
