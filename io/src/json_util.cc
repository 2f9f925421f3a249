// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/json_util.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <set>

#include "handeye/core/transform.h"
#include "text_file.h"

namespace handeye {
namespace {

using Json = nlohmann::json;
using OrderedJson = nlohmann::ordered_json;

// nlohmann keeps the last of two equal keys without a word; a duplicated key
// in a hand-edited file is almost always a mistake, so the parse callback
// tracks where it is (one frame per open object or array) and stops there.
class DuplicateKeyCheck {
 public:
  bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
    using Event = Json::parse_event_t;
    switch (event) {
      case Event::object_start:
        frames_.push_back({false, 0, "", {}});
        break;
      case Event::array_start:
        frames_.push_back({true, 0, "", {}});
        break;
      case Event::key: {
        Frame& top = frames_.back();
        top.key = parsed.get<std::string>();
        if (!top.keys.insert(top.key).second)
          throw InputError("", PathOfOpenValue(), "duplicate key '" + top.key + "' in one object");
        break;
      }
      case Event::value:
        ElementDone();
        break;
      case Event::object_end:
      case Event::array_end:
        frames_.pop_back();
        ElementDone();
        break;
    }
    return true;
  }

 private:
  struct Frame {
    bool is_array;
    std::size_t index;  // arrays: index of the element being parsed
    std::string key;    // objects: key of the member being parsed
    std::set<std::string> keys;
  };

  void ElementDone() {
    if (!frames_.empty() && frames_.back().is_array) ++frames_.back().index;
  }

  std::string PathOfOpenValue() const {
    std::string path;
    for (const Frame& f : frames_)
      path += "/" + (f.is_array ? std::to_string(f.index) : JsonPointerEscape(f.key));
    return path;
  }

  std::vector<Frame> frames_;
};

// "[json.exception.parse_error.101] parse error at line 3, ..." → "parse error at line 3, ...".
std::string StripExceptionId(const std::string& what) {
  const std::size_t close = what.find("] ");
  return (what.rfind("[json.exception.", 0) == 0 && close != std::string::npos)
             ? what.substr(close + 2)
             : what;
}

// nlohmann reports a number that overflows a double without its position;
// find the literal in the text so the user can go straight to it.
std::string LocateLiteral(const std::string& text, const std::string& literal) {
  auto is_number_char = [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == 'e' || c == 'E' ||
           c == '+' || c == '-';
  };
  for (std::size_t pos = text.find(literal); pos != std::string::npos;
       pos = text.find(literal, pos + 1)) {
    const std::size_t end = pos + literal.size();
    if ((pos > 0 && is_number_char(text[pos - 1])) ||
        (end < text.size() && is_number_char(text[end])))
      continue;
    const std::size_t line = 1 + std::count(text.begin(), text.begin() + pos, '\n');
    const std::size_t line_start = pos == 0 ? std::string::npos : text.rfind('\n', pos - 1);
    const std::size_t column = line_start == std::string::npos ? pos + 1 : pos - line_start;
    return " at line " + std::to_string(line) + ", column " + std::to_string(column);
  }
  return "";
}

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

bool IsInlineArray(const OrderedJson& j) {
  return j.is_array() &&
         std::all_of(j.begin(), j.end(), [](const OrderedJson& e) { return !e.is_structured(); });
}

std::string DumpScalar(const OrderedJson& j) {
  // Replace invalid UTF-8 (e.g. in a file name) instead of failing to write.
  return j.dump(-1, ' ', false, OrderedJson::error_handler_t::replace);
}

std::string DumpInline(const OrderedJson& j) {
  std::string out = "[";
  for (std::size_t i = 0; i < j.size(); ++i) out += (i ? ", " : "") + DumpScalar(j[i]);
  return out + "]";
}

void Dump(const OrderedJson& j, int indent, std::string* out) {
  const std::string inner(indent + 2, ' ');
  const std::string outer(indent, ' ');
  if (j.is_object()) {
    if (j.empty()) {
      *out += "{}";
      return;
    }
    *out += "{\n";
    bool first = true;
    for (auto it = j.begin(); it != j.end(); ++it) {
      *out += (first ? "" : ",\n") + inner + DumpScalar(OrderedJson(it.key())) + ": ";
      Dump(it.value(), indent + 2, out);
      first = false;
    }
    *out += "\n" + outer + "}";
  } else if (j.is_array()) {
    if (IsInlineArray(j)) {
      *out += DumpInline(j);
      return;
    }
    *out += "[\n";
    for (std::size_t i = 0; i < j.size(); ++i) {
      *out += (i ? ",\n" : "") + inner;
      Dump(j[i], indent + 2, out);
    }
    *out += "\n" + outer + "]";
  } else {
    *out += DumpScalar(j);
  }
}

// Integral values (counts such as inner_corners) read better as integers;
// below 2^53 a double holds them exactly, so nothing is lost.
OrderedJson NumberJson(double x) {
  if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 9007199254740992.0)
    return OrderedJson(static_cast<std::int64_t>(x));
  return OrderedJson(x);
}

}  // namespace

nlohmann::json ReadJsonFile(const std::string& path) {
  const std::string text = internal::ReadTextFile(path, "a JSON file");
  DuplicateKeyCheck check;
  try {
    return Json::parse(text, std::ref(check));
  } catch (const InputError& e) {
    throw e.WithFile(path);
  } catch (const Json::parse_error& e) {
    throw InputError(path, "", "malformed JSON: " + StripExceptionId(e.what()));
  } catch (const Json::out_of_range& e) {
    // 406: "number overflow parsing '1e999'": a number beyond a double's range.
    const std::string what = StripExceptionId(e.what());
    const std::size_t open = what.find('\'');
    const std::size_t close = what.rfind('\'');
    if (e.id == 406 && open != std::string::npos && close > open) {
      const std::string literal = what.substr(open + 1, close - open - 1);
      throw InputError(path, "",
                       "malformed JSON" + LocateLiteral(text, literal) + ": the number " + literal +
                           " does not fit a double; expected a finite number");
    }
    throw InputError(path, "", "malformed JSON: " + what);
  } catch (const Json::exception& e) {
    throw InputError(path, "", "malformed JSON: " + StripExceptionId(e.what()));
  }
}

std::string JsonPointerEscape(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

// --- JsonReader ---------------------------------------------------------------

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

// --- Targets, matrices, output --------------------------------------------------

TargetSpec TargetSpecFromJson(const JsonReader& target) {
  target.ExpectObject("a target object such as {\"type\": \"checkerboard\", ...}");
  TargetSpec spec;
  spec.type = target.Key("type").NonEmptyString("the target type");
  for (const auto& [key, value] : target.Members("a target object")) {
    if (key == "type") continue;
    const Json& v = value.json();
    if (v.is_number()) {
      spec.values[key] = value.Number();
    } else if (v.is_string()) {
      spec.values[key] = value.String();
    } else if (v.is_array()) {
      spec.values[key] = value.Numbers();
    } else {
      throw value.Error("expected a number, a string or an array of numbers");
    }
  }
  return spec;
}

nlohmann::ordered_json JsonFromTargetSpec(const TargetSpec& spec) {
  OrderedJson out = OrderedJson::object();
  out["type"] = spec.type;
  for (const auto& [key, value] : spec.values) {
    if (const auto* x = std::get_if<double>(&value)) {
      out[key] = NumberJson(*x);
    } else if (const auto* s = std::get_if<std::string>(&value)) {
      out[key] = *s;
    } else {
      OrderedJson list = OrderedJson::array();
      for (double e : std::get<std::vector<double>>(value)) list.push_back(NumberJson(e));
      out[key] = list;
    }
  }
  return out;
}

nlohmann::ordered_json JsonFromMatrix(const Eigen::Matrix4d& M) {
  OrderedJson rows = OrderedJson::array();
  for (int r = 0; r < 4; ++r) rows.push_back({M(r, 0), M(r, 1), M(r, 2), M(r, 3)});
  return rows;
}

nlohmann::ordered_json JsonFromTransform(const Eigen::Isometry3d& T) {
  Eigen::Matrix4d M = T.matrix();
  M.row(3) << 0.0, 0.0, 0.0, 1.0;
  return JsonFromMatrix(M);
}

std::string DumpJson(const nlohmann::ordered_json& value) {
  std::string out;
  Dump(value, 0, &out);
  return out + "\n";
}

}  // namespace handeye
