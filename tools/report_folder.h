// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The report folder of `handeye report` and `calibrate --report`: built
/// beside the old one and swapped in whole, so that an interrupted run leaves
/// the old report or the new one, and no overlay of an earlier run stays.

#include <string>
#include <vector>

#include "handeye/core/calibration.h"
#include "handeye/core/dataset.h"
#include "handeye/report/report.h"
#include "output_paths.h"

namespace handeye::tools {

/// True for a folder the report may replace: empty, or an earlier report
/// (its index.html is one handeye wrote).
bool IsEarlierReport(const std::string& folder);

/// CheckFolderOutput for a report folder.
void CheckReportFolder(const std::vector<NamedPath>& inputs,
                       const std::vector<NamedPath>& other_outputs, const NamedPath& folder);

/// WriteReport into a folder beside `dir`, then swapped in for `dir`
/// (ReplaceFolderAtomically). The summary names the files at `dir`.
ReportSummary WriteReportFolder(const Dataset& dataset, const CalibrationResult& result,
                                const std::string& dir, const ReportOptions& options);

}  // namespace handeye::tools
