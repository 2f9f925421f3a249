// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/json_util.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <set>

#include "handeye/core/calibration.h"
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

nlohmann::ordered_json JsonFromIntrinsicsSigma(const GivenIntrinsicsSigma& sigma) {
  return {{"focal_percent", sigma.focal_percent}, {"principal_point_px", sigma.principal_point_px}};
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
