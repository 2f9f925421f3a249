// SPDX-License-Identifier: GPL-2.0-or-later
// JsonReader (json_util.h): typed access to a JSON value whose errors name the
// file, the JSON pointer and what was expected.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "handeye/core/transform.h"
#include "handeye/io/json_util.h"

namespace handeye {
namespace {

using Json = nlohmann::json;

std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string Quote(const std::string& s) { return "'" + s + "'"; }

}  // namespace

JsonReader::JsonReader(const nlohmann::json* value, std::string file, std::string path)
    : value_(value), file_(std::move(file)), path_(std::move(path)) {}

const nlohmann::json& JsonReader::json() const {
  RequirePresent("a value");
  return *value_;
}

InputError JsonReader::Error(const std::string& expected) const {
  return InputError(file_, path_, expected);
}

void JsonReader::RequirePresent(const std::string& expected) const {
  if (!value_) throw Error("missing key; expected " + expected);
}

std::string JsonReader::TypeDescription() const {
  const Json& v = *value_;
  if (v.is_string()) return "the string \"" + v.get<std::string>() + "\"";
  if (v.is_null()) return "null";
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array of " + std::to_string(v.size());
  if (v.is_number()) return "the number " + v.dump();
  return v.type_name();
}

void JsonReader::ExpectObject(const std::string& what) const {
  RequirePresent(what);
  if (!value_->is_object()) throw Error("expected " + what + ", got " + TypeDescription());
}

JsonReader JsonReader::Key(const std::string& key) const {
  ExpectObject("an object");
  auto it = value_->find(key);
  return JsonReader(it == value_->end() ? nullptr : &*it, file_,
                    path_ + "/" + JsonPointerEscape(key));
}

bool JsonReader::Has(const std::string& key) const {
  ExpectObject("an object");
  return value_->contains(key);
}

std::vector<std::pair<std::string, JsonReader>> JsonReader::Members(const std::string& what) const {
  ExpectObject(what);
  std::vector<std::pair<std::string, JsonReader>> members;
  for (auto it = value_->begin(); it != value_->end(); ++it)
    members.emplace_back(it.key(),
                         JsonReader(&it.value(), file_, path_ + "/" + JsonPointerEscape(it.key())));
  return members;
}

void JsonReader::RejectUnknownKeys(const std::vector<std::string>& known) const {
  ExpectObject("an object");
  for (auto it = value_->begin(); it != value_->end(); ++it) {
    if (std::find(known.begin(), known.end(), it.key()) != known.end()) continue;
    std::string list, nearest;
    std::size_t best = 3;  // more than two edits away is not a typo
    for (const auto& k : known) {
      list += (list.empty() ? "" : ", ") + k;
      const std::size_t d = EditDistance(it.key(), k);
      if (d < best) {
        best = d;
        nearest = k;
      }
    }
    throw InputError(file_, path_ + "/" + JsonPointerEscape(it.key()),
                     "unknown key " + Quote(it.key()) +
                         (nearest.empty() ? "" : " (did you mean " + Quote(nearest) + "?)") +
                         "; expected only: " + list);
  }
}

std::size_t JsonReader::ArraySize(const std::string& what) const {
  RequirePresent(what);
  if (!value_->is_array()) throw Error("expected " + what + ", got " + TypeDescription());
  return value_->size();
}

JsonReader JsonReader::At(std::size_t index) const {
  ArraySize("an array");
  if (index >= value_->size())
    throw std::out_of_range("JsonReader::At: index " + std::to_string(index) + " at " + path_);
  return JsonReader(&(*value_)[index], file_, path_ + "/" + std::to_string(index));
}

double JsonReader::Number() const {
  RequirePresent("a finite number");
  if (!value_->is_number()) throw Error("expected a finite number, got " + TypeDescription());
  const double x = value_->get<double>();
  if (!std::isfinite(x)) throw Error("expected a finite number, got " + TypeDescription());
  return x;
}

double JsonReader::Positive() const {
  RequirePresent("a positive number");
  if (!value_->is_number() || !std::isfinite(value_->get<double>()) || !(value_->get<double>() > 0))
    throw Error("expected a positive number, got " + TypeDescription());
  return value_->get<double>();
}

int JsonReader::Int(int min_value, int max_value) const {
  std::string expected = "an integer";
  if (max_value != std::numeric_limits<int>::max()) {
    expected += " between " + std::to_string(min_value) + " and " + std::to_string(max_value);
  } else if (min_value != std::numeric_limits<int>::min()) {
    expected += " >= " + std::to_string(min_value);
  }
  RequirePresent(expected);
  const Json& v = *value_;
  bool integral = false;
  long double x = 0;
  if (v.is_number_unsigned()) {
    x = static_cast<long double>(v.get<std::uint64_t>());
    integral = true;
  } else if (v.is_number_integer()) {
    x = static_cast<long double>(v.get<std::int64_t>());
    integral = true;
  } else if (v.is_number_float()) {
    const double d = v.get<double>();
    integral = std::isfinite(d) && d == std::floor(d);
    x = d;
  }
  if (!integral || x < min_value || x > max_value)
    throw Error("expected " + expected + ", got " + TypeDescription());
  return static_cast<int>(x);
}

std::string JsonReader::String() const {
  RequirePresent("a string");
  if (!value_->is_string()) throw Error("expected a string, got " + TypeDescription());
  return value_->get<std::string>();
}

std::string JsonReader::NonEmptyString(const std::string& what) const {
  RequirePresent(what + " (a non-empty string)");
  if (!value_->is_string() || value_->get_ref<const std::string&>().empty())
    throw Error("expected " + what + " (a non-empty string), got " + TypeDescription());
  return value_->get<std::string>();
}

std::vector<double> JsonReader::Numbers(int count) const {
  const std::string expected =
      count >= 0 ? "an array of " + std::to_string(count) + " numbers" : "an array of numbers";
  const std::size_t n = ArraySize(expected);
  if (count >= 0 && n != static_cast<std::size_t>(count))
    throw Error("expected " + expected + ", got " + TypeDescription());
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = At(i).Number();
  return out;
}

std::vector<int> JsonReader::Ints(int min_value) const {
  const std::size_t n = ArraySize("an array of integers >= " + std::to_string(min_value));
  std::vector<int> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = At(i).Int(min_value);
  return out;
}

std::vector<Eigen::Vector2d> JsonReader::Points2() const {
  const std::size_t n = ArraySize("an array of pixels [u, v]");
  std::vector<Eigen::Vector2d> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const JsonReader point = At(i);
    if (!point.json().is_array() || point.json().size() != 2)
      throw point.Error("expected a pixel [u, v] of two finite numbers, got " +
                        point.TypeDescription());
    out[i] = Eigen::Vector2d(point.At(0).Number(), point.At(1).Number());
  }
  return out;
}

Eigen::Matrix4d JsonReader::Matrix4() const {
  const std::string expected = "a 4x4 array of numbers (row-major, rows [r, r, r, t])";
  RequirePresent(expected);
  const Json& v = *value_;
  bool shape_ok = v.is_array() && v.size() == 4;
  for (std::size_t r = 0; shape_ok && r < 4; ++r) shape_ok = v[r].is_array() && v[r].size() == 4;
  if (!shape_ok) throw Error("expected " + expected + ", got " + TypeDescription());
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r) {
    const JsonReader row = At(r);
    for (int c = 0; c < 4; ++c) {
      const JsonReader entry = row.At(c);
      if (!entry.json().is_number())
        throw entry.Error("expected a number (an entry of a 4x4 array of numbers), got " +
                          entry.TypeDescription());
      M(r, c) = entry.Number();
    }
  }
  return M;
}

Eigen::Isometry3d JsonReader::Rigid(bool reorthonormalise) const {
  const Eigen::Matrix4d M = Matrix4();
  std::string why;
  const auto T = RigidFromMatrix(M, reorthonormalise, &why);
  if (!T) throw Error("expected " + why);
  return *T;
}

}  // namespace handeye
