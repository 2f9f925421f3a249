// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The targets `handeye simulate` renders and `handeye target` draws: default
// parameters per target type, command-line overrides and target objects read
// from JSON files, shared so both subcommands make the same sheet.

#include <CLI/CLI.hpp>
#include <map>
#include <memory>
#include <string>

#include "handeye/core/target.h"

namespace handeye::tools {

/// Target parameters given on the command line. Empty / zero = the default.
struct TargetOptions {
  std::string type;         ///< checkerboard, charuco or aprilgrid
  std::string target_json;  ///< a file holding a `target` object (or a dataset with one)
  std::string board;        ///< checkerboard inner corners COLSxROWS
  std::string squares;      ///< charuco squares SXxSY
  std::string tags;         ///< aprilgrid tags COLSxROWS
  double square_m = 0;      ///< checkerboard / charuco square (m)
  double marker_m = 0;      ///< charuco marker (m)
  std::string dictionary;   ///< charuco dictionary
  double tag_size_m = 0;    ///< aprilgrid tag (m)
  double tag_spacing = 0;   ///< aprilgrid gap ÷ tag
  int border_bits = 0;      ///< aprilgrid border bits
  /// The options as added to the command, to tell given from defaulted.
  std::map<std::string, CLI::Option*> added;
  bool Given(const std::string& name) const;
};

/// Adds --target-json, --board, --square, --squares, --marker, --dictionary,
/// --tags, --tag-size, --tag-spacing and --border-bits to `cmd`.
void AddTargetOptions(CLI::App* cmd, TargetOptions* options);

/// The target the options describe. Defaults (sized so features span at
/// least about 20 px in the medium cell, on an A3 sheet or less):
/// checkerboard 7×4 inner corners of 40 mm (METRIC's 4×3 of 50 mm when
/// `metric`); charuco 7×5 squares of 55 mm, 40 mm DICT_5X5_100 markers;
/// aprilgrid 6×4 tag36h11 tags of 50 mm, spacing 0.25, 2 border bits
/// (412.5 × 287.5 mm with its margin). Throws InputError naming the option
/// (or the JSON file) that is wrong, including options that do not belong
/// to the type.
std::shared_ptr<const Target> MakeTargetFromOptions(const TargetOptions& options, bool metric);

}  // namespace handeye::tools
