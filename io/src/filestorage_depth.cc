// SPDX-License-Identifier: GPL-2.0-or-later
#include "filestorage_depth.h"

#include <algorithm>
#include <cctype>
#include <vector>

namespace handeye::internal {
namespace {

// OpenCV's test for a character that may stand in a value (cv_isprint):
// every byte from the space up; tabs and line ends are not.
bool Printable(char c) { return static_cast<unsigned char>(c) >= static_cast<unsigned char>(' '); }

// Counts levels as they open and close; `Deeper` says when to stop.
class DepthCounter {
 public:
  explicit DepthCounter(int stop_above) : stop_above_(stop_above) {}
  /// Records the current depth; true once it passes the limit.
  bool Deeper(int depth) {
    deepest_ = std::max(deepest_, depth);
    return deepest_ > stop_above_;
  }
  int deepest() const { return deepest_; }

 private:
  int stop_above_;
  int deepest_ = 0;
};

// Where the text leaves what this model of OpenCV's grammar follows (text
// OpenCV would refuse too, or a reading that differs from OpenCV's), every
// opening bracket from there on counts as one level deeper: never less
// than OpenCV could nest.
int CountRestAsOpening(const std::string& text, std::size_t from, int depth,
                       DepthCounter* counter) {
  for (std::size_t i = from; i < text.size(); ++i)
    if ((text[i] == '[' || text[i] == '{') && counter->Deeper(++depth)) break;
  return counter->deepest();
}

// JSON: strings are always quoted and keys are strings, so brackets outside
// strings are the structure.
int JsonDepth(const std::string& text, int stop_above) {
  DepthCounter counter(stop_above);
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '{' || c == '[') {
      if (counter.Deeper(++depth)) break;
    } else if ((c == '}' || c == ']') && depth > 0) {
      --depth;
    }
  }
  return counter.deepest();
}

// XML: elements nest; comments, declarations and quoted attribute values
// hold no elements, and neither does a quoted string in the content (which
// OpenCV starts only where a value starts: after a tag or a blank).
int XmlDepth(const std::string& text, int stop_above) {
  DepthCounter counter(stop_above);
  int depth = 0;
  bool value_start = true;
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '<') {
      const char next = i + 1 < text.size() ? text[i + 1] : '\0';
      std::size_t end;
      if (text.compare(i, 4, "<!--") == 0) {
        end = text.find("-->", i + 4);
        end = end == std::string::npos ? text.size() : end + 2;
      } else {
        char quote = '\0';
        for (end = i + 1; end < text.size(); ++end) {
          if (quote) {
            if (text[end] == quote) quote = '\0';
          } else if (text[end] == '"' || text[end] == '\'') {
            quote = text[end];
          } else if (text[end] == '>') {
            break;
          }
        }
        if (next == '/') {
          depth = std::max(0, depth - 1);
        } else if (next != '?' && next != '!' && !(end < text.size() && text[end - 1] == '/')) {
          if (counter.Deeper(++depth)) break;
        }
      }
      i = end + 1;
      value_start = true;
    } else if (c == '"' && value_start) {
      const std::size_t end = text.find('"', i + 1);
      i = end == std::string::npos ? text.size() : end + 1;
      value_start = false;
    } else {
      value_start = c == ' ' || c == '\t' || c == '\r' || c == '\n';
      ++i;
    }
  }
  return counter.deepest();
}

// YAML as OpenCV's parser reads it: block collections by the column of their
// first key or '-' (one line may open several: "- - a: b: 1"), flow
// collections by their brackets. Quoted strings start only where a value
// starts; in a flow mapping everything up to ':' is the key.
class YamlDepth {
 public:
  YamlDepth(const std::string& text, int stop_above) : text_(text), counter_(stop_above) {}

  int Run() {
    std::size_t i = 0;
    while (i < text_.size() && !stopped_) {
      std::size_t end = text_.find('\n', i);
      if (end == std::string::npos) end = text_.size();
      i = BlockLine(i, end);
    }
    return counter_.deepest();
  }

 private:
  struct Block {
    std::size_t column;
    bool sequence;
  };
  // After ',' a flow mapping reads a key at once (a '}' there is part of
  // it); after '{' it first looks for the closing bracket.
  enum class Expect { kValue, kKey, kKeyAfterComma, kSeparator };

  int Depth() const { return static_cast<int>(blocks_.size() + flows_.size()); }
  void Open(std::size_t column, bool sequence) {
    if (!sequence && !blocks_.empty() && blocks_.back().column == column && blocks_.back().sequence)
      blocks_.pop_back();  // a key after a '-' list at its key's column ends that list
    if (!blocks_.empty() && blocks_.back().column == column && blocks_.back().sequence == sequence)
      return;
    blocks_.push_back({column, sequence});
    stopped_ = stopped_ || counter_.Deeper(Depth());
  }
  // OpenCV reads "-1" and "-.5" as numbers and any other '-' that starts a
  // block value as a sequence, also without a blank after it ("--x" is a
  // sequence in a sequence; found by fuzz/run).
  bool StartsNumber(std::size_t next, std::size_t end) const {
    return next < end &&
           (std::isdigit(static_cast<unsigned char>(text_[next])) || text_[next] == '.');
  }
  std::size_t SkipSpaces(std::size_t i, std::size_t end) const {
    while (i < end && (text_[i] == ' ' || text_[i] == '\r')) ++i;
    return i;
  }

  // One line outside flow collections; returns where the next line starts.
  std::size_t BlockLine(std::size_t start, std::size_t end) {
    const std::size_t indent = SkipSpaces(start, end) - start;
    std::size_t p = start + indent;
    const std::size_t next_line = end + 1;
    // A '%' line is a directive only before "---" and the first key; after
    // either, OpenCV reads it as a key ("%YAML: [[1]]"; found by fuzz/run).
    if (p < end && text_.compare(p, 3, "---") == 0) {
      document_started_ = true;
      return next_line;
    }
    if (p == end || text_[p] == '#' || (text_[p] == '%' && blocks_.empty() && !document_started_))
      return next_line;
    if (text_.compare(p, 3, "...") == 0) return text_.size();
    while (!blocks_.empty() && blocks_.back().column > indent) blocks_.pop_back();
    // At the start of a line that goes on a mapping, OpenCV reads a key
    // (quotes included); elsewhere a quote starts a string value.
    bool key_position =
        !blocks_.empty() && blocks_.back().column == indent && !blocks_.back().sequence;
    // OpenCV reads one tag per value; a second '!' is text ("!!a !!b: c" is
    // a mapping; found by fuzz/run).
    bool tagged = false;
    while (p < end && !stopped_) {
      const char c = text_[p];
      const std::size_t column = p - start;
      if (c == '-' && !StartsNumber(p + 1, end)) {
        Open(column, true);
        p = SkipSpaces(p + 1, end);
      } else if (c == '!' && !key_position && !tagged) {
        while (p < end && text_[p] != ' ') ++p;
        p = SkipSpaces(p, end);
        tagged = true;
        continue;
      } else if ((c == '[' || c == '{') && !key_position) {
        return Flow(p);
      } else if ((c == '\'' || c == '"' || c == '#') && !key_position) {
        return next_line;
      } else {
        const std::size_t colon = text_.find(':', p);
        if (colon >= end) return next_line;
        Open(column, false);
        p = SkipSpaces(colon + 1, end);
      }
      key_position = false;
      tagged = false;
    }
    return next_line;
  }

  // From an opening bracket to the end of its flow collection, across lines;
  // returns where the line after its end starts.
  std::size_t Flow(std::size_t i) {
    Expect expect = Expect::kValue;
    bool tagged = false;  // as in BlockLine: one tag per value
    while (!stopped_) {
      i = SkipBlanks(i);
      if (i >= text_.size()) return i;
      const char c = text_[i];
      if ((c == ']' || c == '}') && expect != Expect::kKeyAfterComma) {
        if (c != (flows_.back() == '[' ? ']' : '}')) return Unfollowed(i);
        flows_.pop_back();
        ++i;
        if (flows_.empty()) {
          const std::size_t end = text_.find('\n', i);
          return end == std::string::npos ? text_.size() : end + 1;
        }
        expect = Expect::kSeparator;
      } else if (expect == Expect::kSeparator) {
        if (c != ',') return Unfollowed(i);
        expect = flows_.back() == '{' ? Expect::kKeyAfterComma : Expect::kValue;
        tagged = false;
        ++i;
      } else if (expect == Expect::kKey || expect == Expect::kKeyAfterComma) {
        while (i < text_.size() && Printable(text_[i]) && text_[i] != ':') ++i;
        if (i >= text_.size() || text_[i] != ':') return Unfollowed(i);
        expect = Expect::kValue;
        tagged = false;
        ++i;
      } else if (c == '[' || c == '{') {
        flows_.push_back(c);
        stopped_ = counter_.Deeper(Depth());
        expect = c == '{' ? Expect::kKey : Expect::kValue;
        tagged = false;
        ++i;
      } else if (c == '!' && !tagged) {
        while (i < text_.size() && Printable(text_[i]) && text_[i] != ' ') ++i;
        tagged = true;
      } else if (c == '\'' || c == '"') {
        i = SkipQuoted(i);
        if (i == std::string::npos) return Unfollowed(text_.size());
        expect = Expect::kSeparator;
      } else {
        while (i < text_.size() && Printable(text_[i]) && text_[i] != ',' && text_[i] != ']' &&
               text_[i] != '}')
          ++i;
        expect = Expect::kSeparator;
      }
    }
    return text_.size();
  }

  // Blanks, line ends and comments between flow items.
  std::size_t SkipBlanks(std::size_t i) const {
    while (i < text_.size()) {
      const char c = text_[i];
      if (c == '#') {
        i = text_.find('\n', i);
        if (i == std::string::npos) return text_.size();
      } else if (c != ' ' && c != '\t' && c != '\r' && c != '\n') {
        return i;
      }
      ++i;
    }
    return i;
  }

  // A quoted string on one line ('' inside single quotes, \ escapes in
  // double ones); npos when it does not end on its line.
  std::size_t SkipQuoted(std::size_t i) const {
    const char quote = text_[i];
    for (++i; i < text_.size() && Printable(text_[i]); ++i) {
      if (quote == '"' && text_[i] == '\\') {
        ++i;
      } else if (text_[i] == quote) {
        if (quote == '\'' && i + 1 < text_.size() && text_[i + 1] == '\'') {
          ++i;
        } else {
          return i + 1;
        }
      }
    }
    return std::string::npos;
  }

  std::size_t Unfollowed(std::size_t i) {
    CountRestAsOpening(text_, i, Depth(), &counter_);
    stopped_ = true;
    return text_.size();
  }

  const std::string& text_;
  DepthCounter counter_;
  std::vector<Block> blocks_;
  std::vector<char> flows_;
  bool stopped_ = false;
  bool document_started_ = false;  // a "---" line was seen
};

}  // namespace

int FileStorageNestingDepth(const std::string& text, FileStorageSyntax syntax, int stop_above) {
  switch (syntax) {
    case FileStorageSyntax::kJson:
      return JsonDepth(text, stop_above);
    case FileStorageSyntax::kXml:
      return XmlDepth(text, stop_above);
    case FileStorageSyntax::kYaml:
      return YamlDepth(text, stop_above).Run();
  }
  return 0;
}

}  // namespace handeye::internal
