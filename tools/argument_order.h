// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// `report` takes DATASET RESULT, `check` and `evaluate` take RESULT first:
/// files given in the other order get a message that says the order, not
/// only that the format is wrong.

#include <string>
#include <vector>

namespace handeye::tools {

/// A positional argument: its name in the usage, the path given and the
/// `format` values it accepts.
struct PositionalFile {
  std::string name;
  std::string path;
  std::vector<std::string> formats;
};

/// Throws InputError (exit 2) naming the file and the expected `usage` when
/// a file's `format` is not one its place accepts but one another place
/// does. Files that cannot be read or have no `format` are left to the
/// loaders, which say what is wrong with them.
void CheckArgumentOrder(const std::string& usage, const std::vector<PositionalFile>& files);

}  // namespace handeye::tools
