// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Warnings in the JSON files that carry them (result, check): `warnings`,
/// the sentences for people, and `warning_details`, one object per warning in
/// the same order for programs:
///   {"kind": "view_left_out", "camera": "cam0", "pose": "0007", "view": 12, "text": "..."}
/// with `camera`, `pose` and `view` null when the warning is not about one
/// (docs/formats.md).

#include <nlohmann/json.hpp>
#include <vector>

#include "handeye/core/warning.h"
#include "handeye/io/json_util.h"

namespace handeye {

/// Sets `warnings` and `warning_details` of `object`.
void AddWarningsJson(const std::vector<Warning>& warnings, nlohmann::ordered_json* object);

/// The warnings of `object`: from `warning_details` when it has them (they
/// must match `warnings` one for one), else from `warnings` with kind
/// WarningKind::kOther (files written before the details). None when it has
/// neither. Throws InputError at the offending key.
std::vector<Warning> ReadWarningsJson(const JsonReader& object);

}  // namespace handeye
