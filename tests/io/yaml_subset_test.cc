// SPDX-License-Identifier: GPL-2.0-or-later
// The YAML subset reader behind the ROS and Kalibr intrinsics files and the
// tf_static export: structures as those tools write them, and a clear error
// for what the subset does not read.
#include "handeye/io/yaml_subset.h"

#include <catch2/catch.hpp>

#include "handeye/core/error.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;
using nlohmann::json;

TEST_CASE("YAML subset: block and flow collections, scalars, comments", "[io][yaml]") {
  const json doc = ParseYamlSubset(R"(%YAML 1.2
---
# a comment line
name: cam0   # trailing comment
quoted: "a # not a comment"
single: 'it''s'
empty:
number: -1.5e-3
integer: 42
zero_dot: 0.
truthy: true
nothing: ~
url: http://example.com/a:b
list:
- 1
- two
- [3, 4]
- key: value
  other: 5
-
  nested: true
nested:
  deeper:
    flow: {rows: 3, cols: 1, data: [1.0, 2.0,
           3.0]}
  seq_at_key_indent:
  - a
  - b
tagged: !!opencv-matrix
  rows: 1
...
)",
                                   "test.yaml");
  CHECK(doc["name"] == "cam0");
  CHECK(doc["quoted"] == "a # not a comment");
  CHECK(doc["single"] == "it's");
  CHECK(doc["empty"].is_null());
  CHECK(doc["number"].get<double>() == -1.5e-3);
  CHECK(doc["integer"].is_number_integer());
  CHECK(doc["integer"] == 42);
  CHECK(doc["zero_dot"].is_number_float());
  CHECK(doc["truthy"] == true);
  CHECK(doc["nothing"].is_null());
  CHECK(doc["url"] == "http://example.com/a:b");
  REQUIRE(doc["list"].size() == 5);
  CHECK(doc["list"][0] == 1);
  CHECK(doc["list"][1] == "two");
  CHECK(doc["list"][2] == json::array({3, 4}));
  CHECK(doc["list"][3] == json({{"key", "value"}, {"other", 5}}));
  CHECK(doc["list"][4] == json({{"nested", true}}));
  CHECK(doc["nested"]["deeper"]["flow"]["data"] == json::array({1.0, 2.0, 3.0}));
  CHECK(doc["nested"]["seq_at_key_indent"] == json::array({"a", "b"}));
  CHECK(doc["tagged"]["rows"] == 1);
}

TEST_CASE("Full precision numbers read back exactly", "[io][yaml]") {
  const json doc = ParseYamlSubset("x: 0.10000000000000001\ny: -2.2204460492503131e-16\n", "t.yaml");
  CHECK(doc["x"].get<double>() == 0.1);
  CHECK(doc["y"].get<double>() == -2.2204460492503131e-16);
}

TEST_CASE("YAML subset: errors name the file and the line", "[io][yaml]") {
  auto require_error = [](const std::string& text, const std::string& expected) {
    try {
      ParseYamlSubset(text, "bad.yaml");
    } catch (const InputError& e) {
      CHECK(e.file() == "bad.yaml");
      CHECK_THAT(e.what(), Contains(expected));
      return;
    }
    FAIL("accepted:\n" + text);
  };
  require_error("a: 1\na: 2\n", "line 2: duplicate key 'a'");
  require_error("a: 1\n   b: 2\n", "line 2: unexpected indentation");
  require_error("a: 1, 2]\nb: 3\n", "line 1: ']' or '}' without a matching");
  require_error("a: [1, 2\n", "never closed");
  require_error("a: &anchor 1\n", "anchors and aliases");
  require_error("a: |\n  text\n", "block scalars");
  require_error("a:\n\t- 1\n", "a tab in the indentation");
  require_error("a: 1\n---\nb: 2\n", "line 3: a second YAML document");
  require_error("a: \"open\n", "unterminated quoted scalar");
  require_error("a:\n  - 1\n  b: 2\n", "line 3: unexpected indentation");
  CHECK_THROWS_WITH(ReadYamlSubsetFile("/nonexistent/x.yaml"), Contains("/nonexistent/x.yaml: file does not exist"));
}

}  // namespace
}  // namespace handeye
