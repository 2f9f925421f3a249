// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/yaml_file.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <sstream>

#include "handeye/core/error.h"
#include "handeye/io/json_util.h"
#include "text_file.h"
#include "yaml_scalar.h"

namespace handeye {
namespace {

using Json = nlohmann::json;

std::string Where(const YAML::Mark& mark) {
  // yaml-cpp counts lines and columns from 0; editors from 1.
  if (mark.is_null()) return "";
  return "line " + std::to_string(mark.line + 1) + ", column " + std::to_string(mark.column + 1) + ": ";
}

// Aliases make yaml-cpp's tree a graph: `&a {x: *a}` is a cycle and a few
// lines of anchors that repeat each other ("billion laughs") expand to more
// values than memory holds. Calibration files nest a few levels and hold a
// few hundred values, so the JSON made from them is bounded well above that.
constexpr int kMaxDepth = 64;
constexpr std::size_t kMaxValues = 1000000;

struct Converter {
  const std::string& file;
  std::size_t values = 0;

  Json ToJson(const YAML::Node& node, const std::string& path, int depth) {
    if (depth > kMaxDepth)
      throw InputError(file, path, Where(node.Mark()) + "nested more than " + std::to_string(kMaxDepth) +
                                       " levels deep (an alias inside its own anchor?)");
    if (++values > kMaxValues)
      throw InputError(file, path, Where(node.Mark()) + "more than " + std::to_string(kMaxValues) +
                                       " values once aliases are expanded; expected a calibration file");
    switch (node.Type()) {
      case YAML::NodeType::Undefined:
      case YAML::NodeType::Null:
        return nullptr;
      case YAML::NodeType::Scalar:
        // yaml-cpp tags quoted scalars "!" and plain ones "?" (or the explicit
        // tag written, such as !!float, which changes nothing here).
        if (node.Tag() == "!") return node.Scalar();
        return internal::PlainYamlScalar(node.Scalar());
      case YAML::NodeType::Sequence: {
        Json items = Json::array();
        for (const auto& item : node)
          items.push_back(ToJson(item, path + "/" + std::to_string(items.size()), depth + 1));
        return items;
      }
      case YAML::NodeType::Map: {
        Json members = Json::object();
        for (const auto& member : node) {
          if (!member.first.IsScalar())
            throw InputError(file, path, Where(member.first.Mark()) + "expected a plain key, got a collection");
          const std::string& key = member.first.Scalar();
          if (members.contains(key))
            throw InputError(file, path, Where(member.first.Mark()) + "duplicate key '" + key + "'");
          members[key] = ToJson(member.second, path + "/" + JsonPointerEscape(key), depth + 1);
        }
        return members;
      }
    }
    return nullptr;
  }
};

// Where each document starts and whether it holds anything, from the
// parser's events.
class DocumentEvents : public YAML::EventHandler {
 public:
  YAML::Mark start;
  bool content = false;

  void OnDocumentStart(const YAML::Mark& mark) override {
    start = mark;
    content = false;
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override { content = true; }
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {
    content = true;
  }
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    content = true;
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    content = true;
  }
  void OnMapEnd() override {}
};

// Throws unless the text holds at most one document with content (empty
// ones after it are fine: `ros2 topic echo` ends each message with `---`).
// Not YAML::LoadAll: on some malformed input (fuzz/run found ',am0:' at the
// start of a file) yaml-cpp 0.7 hands back the same empty document at the
// same place for ever, and LoadAll collects them until memory runs out.
void RequireOneDocument(const std::string& text, const std::string& file) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  DocumentEvents events;
  int last_start = -1;
  for (int index = 0; parser.HandleNextDocument(events); ++index) {
    if (events.start.pos <= last_start)
      throw InputError(file, "", Where(events.start) + "not readable as YAML (the parser gets no further)");
    last_start = events.start.pos;
    if (index > 0 && events.content)
      throw InputError(file, "", Where(events.start) + "a second YAML document; expected one document");
  }
}

}  // namespace

nlohmann::json ParseYaml(const std::string& text, const std::string& file) {
  YAML::Node document;
  try {
    RequireOneDocument(text, file);
    document = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(file, "", Where(e.mark) + e.msg);
  } catch (const YAML::Exception& e) {
    throw InputError(file, "", std::string("not readable as YAML: ") + e.what());
  }
  return Converter{file}.ToJson(document, "", 0);
}

nlohmann::json ReadYamlFile(const std::string& path) {
  return ParseYaml(internal::ReadTextFile(path, "a YAML file"), path);
}

}  // namespace handeye
