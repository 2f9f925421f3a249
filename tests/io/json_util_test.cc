// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/json_util.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "handeye/core/transform.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;
using nlohmann::json;

// The InputError a callable throws; fails the test when it throws none.
template <typename F>
InputError InputErrorFrom(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  FAIL("expected an InputError");
  throw std::logic_error("unreachable");
}

TEST_CASE("JsonReader getters name the path and what was expected", "[io][json]") {
  const json doc = json::parse(R"({
    "n": 1.5, "i": 4, "f": 4.0, "h": 4.5, "s": "nan", "neg": -2, "big": 1e300,
    "list": [1, 2, "x"], "m": [[1,0,0,0],[0,1,0,0],[0,0,1,0]],
    "a/b": {"c~d": true}
  })");
  const JsonReader root(&doc, "f.json");
  CHECK(root.Key("n").Number() == 1.5);
  CHECK(root.Key("i").Int(1) == 4);
  CHECK(root.Key("f").Int(1) == 4);

  InputError e = InputErrorFrom([&] { root.Key("h").Int(1); });
  CHECK(e.file() == "f.json");
  CHECK(e.json_path() == "/h");
  CHECK_THAT(e.what(), Contains("f.json: at /h: expected an integer >= 1, got the number 4.5"));

  e = InputErrorFrom([&] { root.Key("s").Number(); });
  CHECK(e.json_path() == "/s");
  CHECK_THAT(e.what(), Contains("expected a finite number, got the string \"nan\""));

  e = InputErrorFrom([&] { root.Key("neg").Positive(); });
  CHECK_THAT(e.what(), Contains("at /neg: expected a positive number"));

  e = InputErrorFrom([&] { root.Key("big").Int(0, 10); });
  CHECK_THAT(e.what(), Contains("expected an integer between 0 and 10"));

  e = InputErrorFrom([&] { root.Key("list").Numbers(); });
  CHECK(e.json_path() == "/list/2");

  e = InputErrorFrom([&] { root.Key("missing").Matrix4(); });
  CHECK(e.json_path() == "/missing");
  CHECK_THAT(e.what(), Contains("missing key; expected a 4x4 array of numbers"));

  e = InputErrorFrom([&] { root.Key("m").Matrix4(); });
  CHECK(e.json_path() == "/m");
  CHECK_THAT(e.what(), Contains("expected a 4x4 array of numbers"));
  CHECK_THAT(e.what(), Contains("got an array of 3"));

  // RFC 6901: '/' and '~' in keys are escaped in the path.
  e = InputErrorFrom([&] { root.Key("a/b").Key("c~d").Number(); });
  CHECK(e.json_path() == "/a~1b/c~0d");
  CHECK(JsonPointerEscape("x/y~z") == "x~1y~0z");
}

TEST_CASE("RejectUnknownKeys suggests the key that was probably meant", "[io][json]") {
  const json doc = json::parse(R"({"id": "1", "T_base_eee": 1})");
  const JsonReader root(&doc, "f.json", "/poses/0");
  const InputError e = InputErrorFrom([&] { root.RejectUnknownKeys({"id", "T_base_ee", "images"}); });
  CHECK(e.json_path() == "/poses/0/T_base_eee");
  CHECK_THAT(e.what(), Contains("unknown key 'T_base_eee' (did you mean 'T_base_ee'?)"));
  CHECK_THAT(e.what(), Contains("expected only: id, T_base_ee, images"));
}

TEST_CASE("Rigid accepts a rotation, rejects a non-rigid one unless reorthonormalising",
          "[io][json]") {
  const Eigen::Isometry3d T =
      MakeTransformFromRotationVector(Eigen::Vector3d(0.3, -1.2, 2.0), Eigen::Vector3d(1, 2, 3));
  json doc = json::parse(JsonFromTransform(T).dump());
  CHECK(JsonReader(&doc, "f.json").Rigid(false).matrix() == T.matrix());

  doc[0][0] = doc[0][0].get<double>() + 1e-4;  // rotation off orthonormal by ~1e-4
  const JsonReader skewed(&doc, "f.json", "/T");
  const InputError e = InputErrorFrom([&] { skewed.Rigid(false); });
  CHECK(e.json_path() == "/T");
  CHECK_THAT(e.what(), Contains("off orthonormal"));
  const Eigen::Isometry3d fixed = skewed.Rigid(true);
  CHECK(OrthonormalityError(fixed.linear()) < 1e-12);
  CHECK(RotationDistance(fixed.linear(), T.linear()) < 1e-4);
}

TEST_CASE("TargetSpec converts both ways, other value types are rejected", "[io][json]") {
  const json doc = json::parse(
      R"({"type": "charuco", "squares": [5, 7], "square_size_m": 0.04, "dictionary": "DICT_5X5_100"})");
  const TargetSpec spec = TargetSpecFromJson(JsonReader(&doc, "f.json", "/target"));
  CHECK(spec.type == "charuco");
  CHECK(std::get<std::vector<double>>(spec.values.at("squares")) == std::vector<double>{5, 7});
  CHECK(std::get<double>(spec.values.at("square_size_m")) == 0.04);
  CHECK(std::get<std::string>(spec.values.at("dictionary")) == "DICT_5X5_100");
  // Written back: type first, integers as integers.
  CHECK(JsonFromTargetSpec(spec).dump() ==
        R"({"type":"charuco","dictionary":"DICT_5X5_100","square_size_m":0.04,"squares":[5,7]})");

  const json bad = json::parse(R"({"type": "checkerboard", "inner_corners": {"cols": 4}})");
  const InputError e = InputErrorFrom([&] { TargetSpecFromJson(JsonReader(&bad, "f.json", "/target")); });
  CHECK(e.json_path() == "/target/inner_corners");
  CHECK_THAT(e.what(), Contains("expected a number, a string or an array of numbers"));

  const json untyped = json::parse(R"({"inner_corners": [4, 3]})");
  const InputError e2 =
      InputErrorFrom([&] { TargetSpecFromJson(JsonReader(&untyped, "f.json", "/target")); });
  CHECK(e2.json_path() == "/target/type");
  CHECK_THAT(e2.what(), Contains("missing key; expected the target type"));
}

TEST_CASE("DumpJson is readable and round-trips every double exactly", "[io][json]") {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  j["z"] = "first key stays first";
  j["a"] = 0.1;
  j["T"] = JsonFromMatrix(MakeTransformFromRotationVector(Eigen::Vector3d(0.1, 0.2, 0.3),
                                                          Eigen::Vector3d(1.0 / 3.0, 2e-17, -7.5))
                              .matrix());
  j["ids"] = {1, 2, 3};
  j["empty"] = nlohmann::ordered_json::array();
  const std::string text = DumpJson(j);
  CHECK(text.rfind("{\n  \"z\": \"first key stays first\",\n  \"a\": 0.1,\n  \"T\": [\n    [", 0) ==
        0);
  CHECK_THAT(text, Contains("\"ids\": [1, 2, 3]"));
  CHECK_THAT(text, Contains("\"empty\": []"));
  CHECK(text.back() == '\n');
  const nlohmann::ordered_json back = nlohmann::ordered_json::parse(text);
  CHECK(back == j);  // exact: every double read back bit for bit
}

TEST_CASE("ReadJsonFile reports missing files, syntax errors, overflow and duplicate keys",
          "[io][json]") {
  const std::string dir = test::TempDir("json_util_read");
  InputError e = InputErrorFrom([&] { ReadJsonFile(dir + "/nope.json"); });
  CHECK(e.file() == dir + "/nope.json");
  CHECK_THAT(e.what(), Contains("file does not exist"));

  e = InputErrorFrom([&] { ReadJsonFile(dir); });
  CHECK_THAT(e.what(), Contains("is a folder"));

  test::WriteText(dir + "/syntax.json", "{\n  \"a\": [1,\n   2,,]\n}\n");
  e = InputErrorFrom([&] { ReadJsonFile(dir + "/syntax.json"); });
  CHECK(e.file() == dir + "/syntax.json");
  CHECK_THAT(e.what(), Contains("malformed JSON: parse error at line 3, column"));

  test::WriteText(dir + "/huge.json", "{\n  \"a\": [1,\n     -1e999]\n}\n");
  e = InputErrorFrom([&] { ReadJsonFile(dir + "/huge.json"); });
  CHECK_THAT(e.what(), Contains("at line 3, column 6"));
  CHECK_THAT(e.what(),
             Contains("the number -1e999 does not fit a double; expected a finite number"));

  test::WriteText(dir + "/dup.json",
                  R"({"poses": [{"id": "1"}, {"id": "2", "T_base_ee": 1, "id": "3"}]})");
  e = InputErrorFrom([&] { ReadJsonFile(dir + "/dup.json"); });
  CHECK(e.file() == dir + "/dup.json");
  CHECK(e.json_path() == "/poses/1/id");
  CHECK_THAT(e.what(), Contains("duplicate key 'id'"));
}

}  // namespace
}  // namespace handeye
