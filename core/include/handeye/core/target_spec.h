// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The `target` object of a dataset (SPEC §4) as plain typed values, so that
/// target plugins read their parameters without depending on a JSON library.

#include <array>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace handeye {

/// A target parameter value: a number, a string or a list of numbers.
using TargetValue = std::variant<double, std::string, std::vector<double>>;

/// `target.type` plus its other keys. The typed getters throw InputError with
/// the JSON path `/<key>` (callers prefix `/target` and the file) and what was
/// expected; they never fall back to a default silently.
struct TargetSpec {
  std::string type;
  std::map<std::string, TargetValue> values;

  bool Has(const std::string& key) const { return values.count(key) > 0; }
  /// A finite number > 0.
  double GetPositive(const std::string& key) const;
  /// A number in (0, 1) exclusive, e.g. a ratio.
  double GetFraction(const std::string& key) const;
  /// An integer >= min_value.
  int GetInt(const std::string& key, int min_value) const;
  /// Two integers >= min_value, e.g. `[cols, rows]`.
  std::array<int, 2> GetIntPair(const std::string& key, int min_value) const;
  /// A string; `fallback` when the key is absent (documented defaults only).
  std::string GetString(const std::string& key, const std::string& fallback) const;
  /// Throws InputError for any key not in `known` (catches typos such as
  /// `square_size` for `square_size_m`).
  void RejectUnknownKeys(const std::vector<std::string>& known) const;
};

}  // namespace handeye
