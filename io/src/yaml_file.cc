// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/yaml_file.h"

#include <yaml-cpp/yaml.h>

#include <vector>

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

Json ToJson(const YAML::Node& node, const std::string& file, const std::string& path) {
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
        items.push_back(ToJson(item, file, path + "/" + std::to_string(items.size())));
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
        members[key] = ToJson(member.second, file, path + "/" + JsonPointerEscape(key));
      }
      return members;
    }
  }
  return nullptr;
}

}  // namespace

nlohmann::json ParseYaml(const std::string& text, const std::string& file) {
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(file, "", Where(e.mark) + e.msg);
  } catch (const YAML::Exception& e) {
    throw InputError(file, "", std::string("not readable as YAML: ") + e.what());
  }
  // `ros2 topic echo` ends each message with `---`, which starts an empty
  // second document; only one with content is a second document.
  while (documents.size() > 1 && documents.back().IsNull()) documents.pop_back();
  if (documents.size() > 1)
    throw InputError(file, "", Where(documents[1].Mark()) + "a second YAML document; expected one document");
  if (documents.empty()) return nullptr;
  return ToJson(documents[0], file, "");
}

nlohmann::json ReadYamlFile(const std::string& path) {
  return ParseYaml(internal::ReadTextFile(path, "a YAML file"), path);
}

}  // namespace handeye
