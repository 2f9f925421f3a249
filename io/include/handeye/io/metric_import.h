// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The METRIC / original-tool folder layout (SPEC §8), `handeye import-metric`.

#include <optional>
#include <string>
#include <vector>

#include "handeye/core/dataset.h"
#include "handeye/core/warning.h"

namespace handeye {

/// A folder in the METRIC / original-tool layout (SPEC §8), converted.
struct MetricImport {
  Dataset dataset;                   ///< image paths absolute
  std::optional<GroundTruth> truth;  ///< from FOLDER/GT/ when present
  /// Things a user must see (pose files of one name that disagree, …).
  std::vector<Warning> warnings;
  /// How the folder was read (same-name pose files merged, …): information.
  std::vector<std::string> notes;
};

/// Reads FOLDER/CalibrationInfo.yaml, camera<k>/{image,pose}/ and
/// intrinsic_pars_file.yaml. Throws InputError naming the file and key.
MetricImport ImportMetricFolder(const std::string& folder);

}  // namespace handeye
