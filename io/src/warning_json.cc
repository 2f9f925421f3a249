// SPDX-License-Identifier: GPL-2.0-or-later
// `warnings` and `warning_details` of the result and check files.

#include "handeye/io/warning_json.h"

#include <string>

namespace handeye {

void AddWarningsJson(const std::vector<Warning>& warnings, nlohmann::ordered_json* object) {
  (*object)["warnings"] = WarningTexts(warnings);
  nlohmann::ordered_json details = nlohmann::ordered_json::array();
  for (const Warning& w : warnings) {
    nlohmann::ordered_json entry;
    entry["kind"] = WarningKindName(w.kind);
    entry["camera"] = w.camera.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(w.camera);
    entry["pose"] = w.pose.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(w.pose);
    entry["view"] = w.view ? nlohmann::ordered_json(*w.view) : nlohmann::ordered_json();
    entry["text"] = w.text;
    details.push_back(entry);
  }
  (*object)["warning_details"] = details;
}

namespace {

std::string StringOrEmpty(const JsonReader& value) {
  return value.json().is_null() ? std::string() : value.String();
}

}  // namespace

std::vector<Warning> ReadWarningsJson(const JsonReader& object) {
  std::vector<Warning> warnings;
  if (!object.Has("warnings")) return warnings;
  const JsonReader texts = object.Key("warnings");
  const size_t n = texts.ArraySize("an array of strings");
  if (!object.Has("warning_details")) {
    for (size_t i = 0; i < n; ++i) warnings.push_back(GeneralWarning(WarningKind::kOther, texts.At(i).String()));
    return warnings;
  }
  const JsonReader details = object.Key("warning_details");
  if (details.ArraySize("an array of warning objects") != n)
    throw details.Error("one object per entry of \"warnings\" (" + std::to_string(n) + ")");
  for (size_t i = 0; i < n; ++i) {
    const JsonReader entry = details.At(i);
    Warning w;
    const std::string kind = entry.Key("kind").String();
    const auto parsed = ParseWarningKind(kind);
    // A kind added by a later version reads as "other": its text still says it all.
    w.kind = parsed ? *parsed : WarningKind::kOther;
    w.camera = StringOrEmpty(entry.Key("camera"));
    w.pose = StringOrEmpty(entry.Key("pose"));
    if (!entry.Key("view").json().is_null()) w.view = entry.Key("view").Int(0);
    w.text = entry.Key("text").String();
    if (w.text != texts.At(i).String())
      throw entry.Key("text").Error("the text of warnings[" + std::to_string(i) + "]");
    warnings.push_back(std::move(w));
  }
  return warnings;
}

}  // namespace handeye
