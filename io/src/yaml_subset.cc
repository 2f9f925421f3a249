// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/yaml_subset.h"

#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <regex>
#include <set>
#include <vector>

#include "handeye/core/error.h"
#include "text_file.h"

namespace handeye {
namespace {

using Json = nlohmann::json;

// One logical line: comments stripped, a flow collection that spans several
// physical lines joined into the line where it starts.
struct Line {
  int number = 0;  // 1-based, of the first physical line
  int indent = 0;  // leading spaces
  std::string text;
};

std::string TrimRight(const std::string& s) {
  const auto end = s.find_last_not_of(" \t\r");
  return end == std::string::npos ? "" : s.substr(0, end + 1);
}

std::string Trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  return TrimRight(s.substr(begin));
}

class Failure {
 public:
  explicit Failure(std::string file) : file_(std::move(file)) {}
  InputError At(int line, const std::string& what) const {
    return InputError(file_, "", "line " + std::to_string(line) + ": " + what);
  }

 private:
  std::string file_;
};

// Removes a comment (a '#' at the start or after a blank, outside quotes) and
// returns the change of flow nesting depth ('[' '{' minus ']' '}') on the line.
int StripCommentAndCountDepth(std::string* text, int line, const Failure& fail) {
  int depth = 0;
  char quote = 0;
  for (std::size_t i = 0; i < text->size(); ++i) {
    const char c = (*text)[i];
    if (quote == '"') {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        quote = 0;
      }
    } else if (quote == '\'') {
      if (c == '\'') {
        // '' is an escaped quote inside a single-quoted scalar.
        if (i + 1 < text->size() && (*text)[i + 1] == '\'') {
          ++i;
        } else {
          quote = 0;
        }
      }
    } else if (c == '#' && (i == 0 || (*text)[i - 1] == ' ' || (*text)[i - 1] == '\t')) {
      text->resize(i);
      break;
    } else if ((c == '"' || c == '\'') &&
               (i == 0 || std::strchr(" \t[{,:-", (*text)[i - 1]) != nullptr)) {
      // A quote opens a quoted scalar only where a scalar starts; in the
      // middle of a plain scalar (it's) it is an ordinary character.
      quote = c;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  if (quote) throw fail.At(line, "unterminated quoted scalar (quotes spanning lines are not supported)");
  *text = TrimRight(*text);
  return depth;
}

std::vector<Line> SplitLines(const std::string& input, const Failure& fail) {
  std::vector<Line> lines;
  std::vector<std::string> physical;
  std::size_t start = 0;
  while (start <= input.size()) {
    const std::size_t end = input.find('\n', start);
    physical.push_back(input.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  bool in_document = false;  // after `---` or after the first content line
  bool ended = false;        // after `...` or a second `---`
  for (std::size_t i = 0; i < physical.size(); ++i) {
    const int number = static_cast<int>(i) + 1;
    std::string text = physical[i];
    if (i == 0 && text.rfind("\xEF\xBB\xBF", 0) == 0) text = text.substr(3);  // UTF-8 BOM
    int depth = StripCommentAndCountDepth(&text, number, fail);
    if (Trim(text).empty()) continue;
    if (text == "---" || text.rfind("--- ", 0) == 0 || text == "...") {
      if (text.size() > 3) throw fail.At(number, "content after '---' on the same line is not supported");
      if (text == "..." || in_document) ended = true;
      in_document = true;
      continue;
    }
    if (ended)
      throw fail.At(number, "a second YAML document; expected one document");
    if (text[0] == '%') {
      if (in_document) throw fail.At(number, "a '%' directive inside the document");
      continue;
    }
    in_document = true;
    const std::size_t indent = text.find_first_not_of(' ');
    if (text[indent] == '\t') throw fail.At(number, "a tab in the indentation; YAML indents with spaces");
    Line line{number, static_cast<int>(indent), text.substr(indent)};
    // A flow collection left open continues on the next lines.
    while (depth > 0) {
      if (++i >= physical.size()) throw fail.At(number, "'[' or '{' is never closed");
      std::string more = physical[i];
      depth += StripCommentAndCountDepth(&more, static_cast<int>(i) + 1, fail);
      line.text += " " + Trim(more);
    }
    if (depth < 0) throw fail.At(number, "']' or '}' without a matching '[' or '{'");
    lines.push_back(std::move(line));
  }
  return lines;
}

bool IsSequenceItem(const std::string& text) {
  return text == "-" || text.rfind("- ", 0) == 0;
}

// A plain scalar's value: null, boolean, integer, number or string (YAML 1.2
// core schema, without the special floats, which a calibration file has no
// business containing; they stay strings and fail as "expected a number").
Json PlainScalar(const std::string& text) {
  static const std::regex integer("[-+]?[0-9]+");
  static const std::regex real("[-+]?([0-9]+\\.?[0-9]*|\\.[0-9]+)([eE][-+]?[0-9]+)?");
  if (text.empty() || text == "~" || text == "null" || text == "Null" || text == "NULL") return nullptr;
  if (text == "true" || text == "True" || text == "TRUE") return true;
  if (text == "false" || text == "False" || text == "FALSE") return false;
  if (std::regex_match(text, integer)) {
    errno = 0;
    const long long value = std::strtoll(text.c_str(), nullptr, 10);
    if (errno == 0) return static_cast<std::int64_t>(value);
  }
  if (std::regex_match(text, real)) {
    errno = 0;
    const double value = std::strtod(text.c_str(), nullptr);
    if (errno == 0) return value;
  }
  return text;
}

// Reads values from one logical line: flow collections, quoted and plain scalars.
class FlowReader {
 public:
  FlowReader(const std::string& text, int line, const Failure& fail)
      : text_(text), line_(line), fail_(fail) {}

  // The whole text as one value (block context: a plain scalar runs to the end).
  Json ReadAll() {
    SkipSpaces();
    SkipTag();
    Json value = AtEnd() ? Json(nullptr) : ReadValue(/*in_flow=*/false);
    SkipSpaces();
    if (!AtEnd()) throw fail_.At(line_, "unexpected '" + text_.substr(pos_) + "' after a value");
    return value;
  }

  // A key at the start of a block mapping line: a quoted or plain scalar up
  // to ':' followed by a blank or the end. Returns false when the text is not
  // a mapping entry; then nothing is consumed.
  bool ReadKey(std::string* key) {
    const std::size_t start = pos_;
    if (!AtEnd() && (text_[pos_] == '"' || text_[pos_] == '\'')) {
      *key = ReadQuoted();
      SkipSpaces();
    } else {
      std::size_t colon = pos_;
      while (colon < text_.size() && !IsMappingColon(colon)) ++colon;
      if (colon >= text_.size() || text_[pos_] == '[' || text_[pos_] == '{') {
        pos_ = start;
        return false;
      }
      *key = Trim(text_.substr(pos_, colon - pos_));
      pos_ = colon;
    }
    if (AtEnd() || !IsMappingColon(pos_)) {
      pos_ = start;
      return false;
    }
    ++pos_;
    return true;
  }

  // What is left after a key, tags skipped: "" when the value is on the next lines.
  std::string Rest() {
    SkipSpaces();
    SkipTag();
    return text_.substr(pos_);
  }

 private:
  bool AtEnd() const { return pos_ >= text_.size(); }
  void SkipSpaces() {
    while (!AtEnd() && (text_[pos_] == ' ' || text_[pos_] == '\t')) ++pos_;
  }
  bool IsMappingColon(std::size_t i) const {
    return text_[i] == ':' && (i + 1 == text_.size() || text_[i + 1] == ' ' || text_[i + 1] == '\t');
  }
  // Tags such as `!!opencv-matrix` or `!!float` only name a type; the value
  // is read the same without them.
  void SkipTag() {
    if (AtEnd() || text_[pos_] != '!') return;
    while (!AtEnd() && text_[pos_] != ' ') ++pos_;
    SkipSpaces();
  }

  Json ReadValue(bool in_flow) {
    SkipSpaces();
    SkipTag();
    if (AtEnd()) return nullptr;
    const char c = text_[pos_];
    if (c == '[') return ReadSequence();
    if (c == '{') return ReadMapping();
    if (c == '"' || c == '\'') return ReadQuoted();
    if (c == '&' || c == '*') throw fail_.At(line_, "anchors and aliases (& and *) are not supported");
    if (c == '|' || c == '>') throw fail_.At(line_, "block scalars (| and >) are not supported");
    std::size_t end = pos_;
    if (in_flow) {
      while (end < text_.size() && std::strchr(",[]{}", text_[end]) == nullptr && !IsMappingColon(end)) ++end;
    } else {
      end = text_.size();
    }
    const std::string plain = Trim(text_.substr(pos_, end - pos_));
    pos_ = end;
    return PlainScalar(plain);
  }

  Json ReadSequence() {
    ++pos_;  // '['
    Json items = Json::array();
    while (true) {
      SkipSpaces();
      if (AtEnd()) throw fail_.At(line_, "'[' is never closed");
      if (text_[pos_] == ']') {
        ++pos_;
        return items;
      }
      items.push_back(ReadValue(true));
      SkipSpaces();
      if (!AtEnd() && text_[pos_] == ',') {
        ++pos_;
      } else if (AtEnd() || text_[pos_] != ']') {
        throw fail_.At(line_, "expected ',' or ']' in a flow sequence");
      }
    }
  }

  Json ReadMapping() {
    ++pos_;  // '{'
    Json members = Json::object();
    while (true) {
      SkipSpaces();
      if (AtEnd()) throw fail_.At(line_, "'{' is never closed");
      if (text_[pos_] == '}') {
        ++pos_;
        return members;
      }
      std::string key;
      if (text_[pos_] == '"' || text_[pos_] == '\'') {
        key = ReadQuoted();
      } else {
        const std::size_t start = pos_;
        while (!AtEnd() && text_[pos_] != ':' && text_[pos_] != ',' && text_[pos_] != '}') ++pos_;
        key = Trim(text_.substr(start, pos_ - start));
      }
      SkipSpaces();
      if (AtEnd() || text_[pos_] != ':') throw fail_.At(line_, "expected 'key: value' in a flow mapping");
      ++pos_;
      if (members.contains(key)) throw fail_.At(line_, "duplicate key '" + key + "'");
      members[key] = ReadValue(true);
      SkipSpaces();
      if (!AtEnd() && text_[pos_] == ',') {
        ++pos_;
      } else if (AtEnd() || text_[pos_] != '}') {
        throw fail_.At(line_, "expected ',' or '}' in a flow mapping");
      }
    }
  }

  std::string ReadQuoted() {
    const char quote = text_[pos_++];
    std::string out;
    while (true) {
      if (AtEnd()) throw fail_.At(line_, "unterminated quoted scalar");
      const char c = text_[pos_++];
      if (quote == '\'' && c == '\'') {
        if (!AtEnd() && text_[pos_] == '\'') {
          out += '\'';
          ++pos_;
          continue;
        }
        return out;
      }
      if (quote == '"' && c == '"') return out;
      if (quote == '"' && c == '\\' && !AtEnd()) {
        const char e = text_[pos_++];
        switch (e) {
          case 'n': out += '\n'; break;
          case 't': out += '\t'; break;
          case '0': out += '\0'; break;
          default: out += e;  // \" \\ \/ and the rest as written
        }
        continue;
      }
      out += c;
    }
  }

  const std::string& text_;
  int line_;
  const Failure& fail_;
  std::size_t pos_ = 0;
};

class BlockParser {
 public:
  BlockParser(std::vector<Line> lines, const Failure& fail) : lines_(std::move(lines)), fail_(fail) {}

  Json Document() {
    if (lines_.empty()) return nullptr;
    Json value = Node(lines_[0].indent);
    if (pos_ < lines_.size())
      throw fail_.At(lines_[pos_].number, "unexpected indentation (" +
                                              std::to_string(lines_[pos_].indent) + " spaces)");
    return value;
  }

 private:
  // The node whose first line is lines_[pos_], at indentation `indent`.
  Json Node(int indent) {
    Line& line = lines_[pos_];
    if (IsSequenceItem(line.text)) return Sequence(indent);
    std::string key;
    FlowReader probe(line.text, line.number, fail_);
    if (probe.ReadKey(&key)) return Mapping(indent);
    ++pos_;
    return FlowReader(line.text, line.number, fail_).ReadAll();
  }

  Json Sequence(int indent) {
    Json items = Json::array();
    while (pos_ < lines_.size() && lines_[pos_].indent == indent && IsSequenceItem(lines_[pos_].text)) {
      Line& line = lines_[pos_];
      const std::string rest = line.text.substr(1);
      const std::size_t skip = rest.find_first_not_of(' ');
      if (skip == std::string::npos) {
        ++pos_;
        items.push_back(pos_ < lines_.size() && lines_[pos_].indent > indent ? Node(lines_[pos_].indent)
                                                                              : Json(nullptr));
        continue;
      }
      // "- key: value" or "- 0.1": the item is what follows the dash, as if it
      // stood on its own line at its column (later lines of the item align there).
      line.indent = indent + 1 + static_cast<int>(skip);
      line.text = rest.substr(skip);
      items.push_back(Node(line.indent));
    }
    return items;
  }

  Json Mapping(int indent) {
    Json members = Json::object();
    std::set<std::string> keys;
    while (pos_ < lines_.size() && lines_[pos_].indent == indent) {
      const Line& line = lines_[pos_];
      FlowReader reader(line.text, line.number, fail_);
      std::string key;
      if (!reader.ReadKey(&key))
        throw fail_.At(line.number, "expected 'key: value' (a mapping entry), got '" + line.text + "'");
      if (!keys.insert(key).second) throw fail_.At(line.number, "duplicate key '" + key + "'");
      const std::string rest = reader.Rest();
      const int number = line.number;
      ++pos_;
      if (!rest.empty()) {
        members[key] = FlowReader(rest, number, fail_).ReadAll();
      } else if (pos_ < lines_.size() && lines_[pos_].indent > indent) {
        members[key] = Node(lines_[pos_].indent);
      } else if (pos_ < lines_.size() && lines_[pos_].indent == indent &&
                 IsSequenceItem(lines_[pos_].text)) {
        // YAML lets a block sequence sit at its key's indentation (`d:\n- 0.1`).
        members[key] = Sequence(indent);
      } else {
        members[key] = nullptr;
      }
    }
    return members;
  }

  std::vector<Line> lines_;
  const Failure& fail_;
  std::size_t pos_ = 0;
};

}  // namespace

nlohmann::json ParseYamlSubset(const std::string& text, const std::string& file) {
  const Failure fail(file);
  return BlockParser(SplitLines(text, fail), fail).Document();
}

nlohmann::json ReadYamlSubsetFile(const std::string& path) {
  return ParseYamlSubset(internal::ReadTextFile(path, "a YAML file"), path);
}

}  // namespace handeye
