// SPDX-License-Identifier: GPL-2.0-or-later
#include "argument_order.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "handeye/core/error.h"
#include "handeye/io/json_util.h"

namespace handeye::tools {
namespace {

// The file's top-level "format" string; "" when there is none.
std::string FormatOf(const std::string& path) {
  try {
    const nlohmann::json root = ReadJsonFile(path);
    const auto it = root.is_object() ? root.find("format") : root.end();
    return it != root.end() && it->is_string() ? it->get<std::string>() : "";
  } catch (const std::exception&) {
    return "";  // the loader reports it
  }
}

bool Accepts(const PositionalFile& place, const std::string& format) {
  return std::find(place.formats.begin(), place.formats.end(), format) != place.formats.end();
}

}  // namespace

void CheckArgumentOrder(const std::string& usage, const std::vector<PositionalFile>& files) {
  for (const PositionalFile& file : files) {
    const std::string format = FormatOf(file.path);
    if (format.empty() || Accepts(file, format)) continue;
    for (const PositionalFile& other : files)
      if (&other != &file && Accepts(other, format))
        throw InputError(file.path, "/format",
                         "a " + format + " file given as " + file.name +
                             "; it belongs in the place of " + other.name + ": the order is `" +
                             usage + "`");
  }
}

}  // namespace handeye::tools
