// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// YAML input (ROS `camera_info` files and messages, Kalibr camchains, the
/// tf_static export) read with yaml-cpp and handed back as JSON, so that
/// io::JsonReader reports problems with the file and a path
/// (`/cam0/intrinsics`) as for every JSON format.
///
/// One document (a `%YAML` directive and `---` / `...` are fine; a second
/// document is an error). Anchors and aliases are resolved; tags such as
/// `!!opencv-matrix` are ignored. Plain scalars become numbers when they read
/// as one (YAML 1.2 core schema: `3`, `-0.1`, `1e-05`, `0.`), booleans for
/// true/false, null for `~`, `null` or nothing; `.inf` and `.nan`, which a
/// calibration file has no business containing, and every other plain
/// scalar stay strings (so they fail as "expected a number"); quoted scalars
/// are always strings. Keys must be scalars; a key given twice is an error
/// naming its line.
///
/// Thread safety: the functions are reentrant (no shared state).

#include <nlohmann/json.hpp>
#include <string>

namespace handeye {

/// Parses YAML text. `file` names the source in error messages.
/// Throws InputError(file, path, "line N, column M: ...") on malformed YAML,
/// several documents, a duplicate key or a key that is not a scalar.
nlohmann::json ParseYaml(const std::string& text, const std::string& file);

/// Reads and parses a YAML file. Throws InputError naming the path when it is
/// missing, unreadable or not YAML.
nlohmann::json ReadYamlFile(const std::string& path);

}  // namespace handeye
