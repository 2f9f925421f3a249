// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Atomic file writes (SPEC §6: a failed run never leaves a half-written file).

#include <string>

namespace handeye {

/// Writes `content` to a temporary file beside `path`, then renames it over
/// `path`: readers never see a half-written file. Throws InputError naming
/// the path when the folder is missing or not writable.
void WriteFileAtomically(const std::string& path, const std::string& content);

}  // namespace handeye
