// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Reading a whole input file, with the errors every loader gives. Internal to
// the io library.

#include <string>

namespace handeye::internal {

/// The whole content of the file at `path`. Throws InputError naming the path
/// when it does not exist, is a folder ("is a folder; expected `expected`",
/// e.g. "a JSON file") or cannot be read.
std::string ReadTextFile(const std::string& path, const std::string& expected);

}  // namespace handeye::internal
