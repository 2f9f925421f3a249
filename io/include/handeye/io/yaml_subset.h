// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// A reader for the part of YAML that camera calibration files use: ROS
/// `camera_info` files and messages, Kalibr camchains. OpenCV's FileStorage
/// cannot read them (it wants a `%YAML:1.0` header and rejects block
/// sequences at their parent's indentation, as in `d:\n- 0.1`), and a full
/// YAML library is a large dependency for three small formats.
///
/// Supported: block mappings and block sequences (indentation by spaces),
/// flow sequences and mappings (`[1, 2]`, `{rows: 3}`, also across lines),
/// plain, 'single' and "double" quoted scalars, `#` comments, a `%` directive
/// and `---` / `...` around one document, and tags such as `!!opencv-matrix`
/// (ignored). Not supported, with an error naming the line: anchors and
/// aliases, block scalars (`|`, `>`), complex keys, several documents, tabs
/// in indentation.
///
/// The document comes back as JSON so that io::JsonReader reports problems
/// with the file and a path (`/cam0/intrinsics`). Plain scalars become
/// numbers when they read as one (`3`, `-0.1`, `1e-05`, `0.`), booleans for
/// true/false, null for `~`, `null` or nothing; everything else, and every
/// quoted scalar, is a string. Keys are strings; a key given twice is an error.
///
/// Thread safety: the functions are reentrant (no shared state).

#include <nlohmann/json.hpp>
#include <string>

namespace handeye {

/// Parses YAML text. `file` names the source in error messages.
/// Throws InputError(file, "", "line N: ...") on what the subset does not read.
nlohmann::json ParseYamlSubset(const std::string& text, const std::string& file);

/// Reads and parses a YAML file. Throws InputError naming the path when it is
/// missing, unreadable or not in the subset.
nlohmann::json ReadYamlSubsetFile(const std::string& path);

}  // namespace handeye
