// SPDX-License-Identifier: GPL-2.0-or-later
// The YAML reader (yaml-cpp, handed back as JSON) behind the ROS and Kalibr
// intrinsics files and the tf_static export: structures as those tools write
// them, how scalars are typed, and errors that name the file and the line.
#include "handeye/io/yaml_file.h"

#include <catch2/catch.hpp>

#include "handeye/core/error.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;
using nlohmann::json;

TEST_CASE("YAML: block and flow collections, scalars, comments", "[io][yaml]") {
  const json doc = ParseYaml(R"(%YAML 1.2
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
  const json doc = ParseYaml("x: 0.10000000000000001\ny: -2.2204460492503131e-16\n", "t.yaml");
  CHECK(doc["x"].get<double>() == 0.1);
  CHECK(doc["y"].get<double>() == -2.2204460492503131e-16);
}

TEST_CASE("YAML: anchors, block scalars and typed scalars", "[io][yaml]") {
  const json doc = ParseYaml(R"(base: &b {rows: 1, cols: 2}
copy: *b
text: |
  two
  lines
quoted_number: "1.5"
special: .inf
not_a_number: 1.2.3
hex: 0x10
big: 123456789012345678901234567890
)",
                             "t.yaml");
  CHECK(doc["copy"] == doc["base"]);
  CHECK(doc["text"] == "two\nlines\n");
  CHECK(doc["quoted_number"] == "1.5");
  CHECK(doc["special"] == ".inf");
  CHECK(doc["not_a_number"] == "1.2.3");
  CHECK(doc["hex"] == "0x10");
  CHECK(doc["big"].get<double>() == 123456789012345678901234567890.0);
  CHECK(ParseYaml("", "empty.yaml").is_null());
  // A trailing `---` (ros2 topic echo) starts no second document.
  CHECK(ParseYaml("a: 1\n---\n", "t.yaml") == json({{"a", 1}}));
}

TEST_CASE("YAML: errors name the file and the line", "[io][yaml]") {
  auto require_error = [](const std::string& text, const std::string& expected) {
    try {
      ParseYaml(text, "bad.yaml");
    } catch (const InputError& e) {
      CHECK(e.file() == "bad.yaml");
      CHECK_THAT(e.what(), Contains(expected));
      return;
    }
    FAIL("accepted:\n" + text);
  };
  require_error("a: 1\na: 2\n", "line 2, column 1: duplicate key 'a'");
  require_error("outer:\n  a: 1\n  a: 2\n", "bad.yaml: at /outer: line 3, column 3: duplicate key 'a'");
  require_error("a: 1\n   b: 2\n", "line 2");
  require_error("a: [1, 2\n", "line 2");
  require_error("a: 1\n---\nb: 2\n", "line 2, column 1: a second YAML document");
  // fuzz/run: yaml-cpp's LoadAll ran out of memory on this (intrinsics_kalibr).
  require_error(",am0:\n  ccm0a:\nam0:\n", "line 1, column 1: not readable as YAML (the parser gets no further)");
  require_error("? [1, 2]\n: x\n", "line 1, column 3: expected a plain key, got a collection");
  // Aliases that make a cycle, and anchors that expand to 10^9 values.
  require_error("a: &a {x: *a}\n", "nested more than 64 levels deep (an alias inside its own anchor?)");
  std::string laughs = "l0: &l0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n";
  for (int i = 1; i < 9; ++i)
    laughs += "l" + std::to_string(i) + ": &l" + std::to_string(i) + " [" +
              [&] {
                std::string refs;
                for (int k = 0; k < 10; ++k) refs += (k ? ", *l" : "*l") + std::to_string(i - 1);
                return refs;
              }() +
              "]\n";
  require_error(laughs, "more than 1000000 values once aliases are expanded");
  CHECK_THROWS_WITH(ReadYamlFile("/nonexistent/x.yaml"), Contains("/nonexistent/x.yaml: file does not exist"));
}

}  // namespace
}  // namespace handeye
