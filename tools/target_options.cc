// SPDX-License-Identifier: GPL-2.0-or-later
#include "target_options.h"

#include <cmath>
#include <vector>

#include "cli_numbers.h"
#include "handeye/core/error.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/json_util.h"

namespace handeye::tools {
namespace {

// Checkerboard: 7×4 inner corners of 40 mm. cols + rows is odd, so it is not
// 180°-ambiguous; its 8×5 squares (320 × 200 mm, 400 × 280 mm with the white
// margin) fit on an A3 sheet, compact enough to carry on a flange without
// collisions; and a 40 mm square still spans ≈ 18 px at 4 m in the large cell.
constexpr int kCheckerCols = 7, kCheckerRows = 4;
constexpr double kCheckerSquareM = 0.04;
// METRIC's A4 board: 4×3 inner corners, 50 mm.
constexpr int kMetricCols = 4, kMetricRows = 3;
constexpr double kMetricSquareM = 0.05;
// ChArUco: 7×5 squares of 55 mm (385 × 275 mm, 400 × 290 mm with the margin:
// A3), 24 inner corners; 40 mm markers span ≈ 20 px at 2.7 m in the medium
// cell (fx ≈ 1371 px). DICT_5X5_100: 17 markers needed; 5×5 bits keep a cell
// at 5.7 mm, where 6×6 would shrink it to 5 mm.
constexpr int kCharucoSquaresX = 7, kCharucoSquaresY = 5;
constexpr double kCharucoSquareM = 0.055, kCharucoMarkerM = 0.04;
constexpr const char* kCharucoDictionary = "DICT_5X5_100";
// AprilGrid: 6×4 tags of 50 mm with a 12.5 mm gap (412.5 × 287.5 mm with the
// black corner squares and margin: A3), 96 corners; a tag spans ≈ 25 px at
// 2.7 m in the medium cell.
constexpr int kAprilTagsX = 6, kAprilTagsY = 4;
constexpr double kAprilTagM = 0.05, kAprilSpacing = 0.25;

/// Two counts as a target's values hold them.
std::vector<double> Counts(std::pair<int, int> counts) {
  return {double(counts.first), double(counts.second)};
}

/// A `target` object from a file: the object itself, or the `target` of a
/// dataset or observations file.
TargetSpec SpecFromFile(const std::string& path, std::string* path_in_file) {
  const nlohmann::json root = ReadJsonFile(path);
  const JsonReader file(&root, path);
  const bool nested = root.is_object() && root.contains("target") && !root.contains("type");
  *path_in_file = nested ? "/target" : "";
  return TargetSpecFromJson(nested ? file.Key("target") : file);
}

}  // namespace

bool TargetOptions::Given(const std::string& name) const {
  const auto it = added.find(name);
  return it != added.end() && it->second && it->second->count() > 0;
}

void AddTargetOptions(CLI::App* cmd, TargetOptions* o) {
  o->added["--target-json"] = cmd->add_option("--target-json", o->target_json,
                                              "file with a `target` object (docs/formats.md#targets), or a dataset "
                                              "holding one, instead of the options below");
  o->added["--board"] =
      cmd->add_option("--board", o->board, "checkerboard inner corners COLSxROWS (default 7x4)");
  o->added["--square"] =
      cmd->add_option("--square", o->square_m,
                      "checkerboard or charuco square size in metres (default 0.04 / 0.055)")
          ->check(PositiveNumber("a positive size in metres"));
  o->added["--squares"] =
      cmd->add_option("--squares", o->squares, "charuco squares SXxSY (default 7x5)");
  o->added["--marker"] =
      cmd->add_option("--marker", o->marker_m, "charuco marker size in metres (default 0.04)")
          ->check(PositiveNumber("a positive size in metres"));
  o->added["--dictionary"] = cmd->add_option("--dictionary", o->dictionary,
                                             "charuco OpenCV dictionary (default DICT_5X5_100)");
  o->added["--tags"] = cmd->add_option("--tags", o->tags, "aprilgrid tags COLSxROWS (default 6x4)");
  o->added["--tag-size"] =
      cmd->add_option("--tag-size", o->tag_size_m,
                      "aprilgrid tag size in metres, black square edge (default 0.05)")
          ->check(PositiveNumber("a positive size in metres"));
  o->added["--tag-spacing"] = cmd->add_option(
      "--tag-spacing", o->tag_spacing, "aprilgrid gap between tags / tag size (default 0.25)")
          ->check(PositiveNumber("a positive ratio of gap to tag size"));
  o->added["--border-bits"] = cmd->add_option(
      "--border-bits", o->border_bits, "aprilgrid black border width in bits, 1 or 2 (default 2)")
          ->check(IntegerIn(1, 2, "1 or 2 border bits"));
}

std::shared_ptr<const Target> MakeTargetFromOptions(const TargetOptions& o, bool metric) {
  // Which options belong to which type; anything else given is a mistake.
  const std::map<std::string, std::vector<std::string>> own = {
      {"checkerboard", {"--board", "--square"}},
      {"charuco", {"--squares", "--square", "--marker", "--dictionary"}},
      {"aprilgrid", {"--tags", "--tag-size", "--tag-spacing", "--border-bits"}}};
  TargetSpec spec;
  std::string file_path_prefix;
  if (!o.target_json.empty()) {
    spec = SpecFromFile(o.target_json, &file_path_prefix);
    if (!o.type.empty() && o.type != spec.type)
      throw InputError("", "--target",
                       "expected the type of " + o.target_json + " ('" + spec.type +
                           "') or none, got '" + o.type + "'");
    for (const auto& [name, option] : o.added)
      if (name != "--target-json" && o.Given(name))
        throw InputError("", name, "expected either --target-json or target options, not both");
  } else {
    spec.type = o.type.empty() ? "checkerboard" : o.type;
    const auto it = own.find(spec.type);
    if (it == own.end()) {
      std::string known;
      bool registered = false;
      for (const auto& type : KnownTargetTypes()) {
        known += (known.empty() ? "" : ", ") + type;
        registered = registered || type == spec.type;
      }
      if (!registered)
        throw InputError("", "--target",
                         "unknown target type '" + spec.type + "'; expected one of: " + known);
      throw InputError("", "--target",
                       "no default '" + spec.type +
                           "' target; expected checkerboard, charuco or "
                           "aprilgrid, or --target-json with the target object");
    }
    for (const auto& [name, value] : {std::pair<const char*, double>{"--square", o.square_m},
                                      {"--marker", o.marker_m},
                                      {"--tag-size", o.tag_size_m},
                                      {"--tag-spacing", o.tag_spacing}})
      if (o.Given(name) && !(std::isfinite(value) && value > 0))
        throw InputError("", name, "expected a positive number, got " + std::to_string(value));
    for (const auto& [name, option] : o.added) {
      if (name == "--target-json" || !o.Given(name)) continue;
      bool belongs = false;
      for (const auto& mine : it->second) belongs = belongs || mine == name;
      if (!belongs)
        throw InputError("", name,
                         "expected only with a target type that has it, not " + spec.type);
    }
    auto& v = spec.values;
    if (spec.type == "checkerboard") {
      v["inner_corners"] =
          o.Given("--board") ? Counts(ParseTwoCounts("--board", o.board, "COLSxROWS inner corners"))
          : metric           ? std::vector<double>{kMetricCols, kMetricRows}
                             : std::vector<double>{kCheckerCols, kCheckerRows};
      v["square_size_m"] = o.Given("--square") ? o.square_m
                           : metric            ? kMetricSquareM
                                               : kCheckerSquareM;
    } else if (spec.type == "charuco") {
      v["squares"] = o.Given("--squares")
                         ? Counts(ParseTwoCounts("--squares", o.squares, "SXxSY squares"))
                         : std::vector<double>{kCharucoSquaresX, kCharucoSquaresY};
      v["square_size_m"] = o.Given("--square") ? o.square_m : kCharucoSquareM;
      v["marker_size_m"] = o.Given("--marker") ? o.marker_m : kCharucoMarkerM;
      v["dictionary"] = o.Given("--dictionary") ? o.dictionary : std::string(kCharucoDictionary);
    } else {
      v["tags"] = o.Given("--tags") ? Counts(ParseTwoCounts("--tags", o.tags, "COLSxROWS tags"))
                                    : std::vector<double>{kAprilTagsX, kAprilTagsY};
      v["tag_size_m"] = o.Given("--tag-size") ? o.tag_size_m : kAprilTagM;
      v["tag_spacing"] = o.Given("--tag-spacing") ? o.tag_spacing : kAprilSpacing;
      if (o.Given("--border-bits")) v["border_bits"] = double(o.border_bits);
    }
  }
  try {
    return MakeTarget(spec);
  } catch (const InputError& e) {
    if (!o.target_json.empty())
      throw InputError(o.target_json, file_path_prefix + e.json_path(), e.expected());
    throw InputError("", "--target" + e.json_path(), e.expected());
  }
}

}  // namespace handeye::tools
