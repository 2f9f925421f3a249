// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The value of a plain (unquoted) YAML scalar, shared by the YAML readers.
// Internal to the io library.

#include <nlohmann/json.hpp>
#include <string>

namespace handeye::internal {

/// YAML 1.2 core schema without the special floats: null for "", "~" and
/// null/Null/NULL; true/false in the three spellings; an integer for
/// [-+]?[0-9]+ that fits 64 bits; a double for
/// [-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)? that is finite;
/// otherwise the text as a string.
nlohmann::json PlainYamlScalar(const std::string& text);

}  // namespace handeye::internal
