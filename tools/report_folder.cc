// SPDX-License-Identifier: GPL-2.0-or-later
#include "report_folder.h"

#include <filesystem>
#include <fstream>
#include <iterator>

#include "handeye/io/atomic_file.h"

namespace handeye::tools {
namespace {

namespace fs = std::filesystem;

// What the report's index.html says it is (report_html.cc writes this title).
constexpr char kReportTitle[] = "<title>Hand-eye calibration report</title>";

// "out/" and "out" are one folder; the swap renames it, so it needs its name.
std::string WithoutTrailingSlash(const std::string& dir) {
  fs::path path = fs::path(dir).lexically_normal();
  if (!path.has_filename() && path.has_parent_path()) path = path.parent_path();
  return path.string();
}

}  // namespace

bool IsEarlierReport(const std::string& folder) {
  std::error_code ec;
  if (fs::is_empty(folder, ec) && !ec) return true;
  std::ifstream in(fs::path(folder) / "index.html", std::ios::binary);
  std::string head(4096, '\0');
  in.read(&head[0], static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head.find(kReportTitle) != std::string::npos;
}

void CheckReportFolder(const std::vector<NamedPath>& inputs,
                       const std::vector<NamedPath>& other_outputs, const NamedPath& folder) {
  CheckFolderOutput(inputs, other_outputs, folder, &IsEarlierReport);
}

ReportSummary WriteReportFolder(const Dataset& dataset, const CalibrationResult& result,
                                const std::string& dir, const ReportOptions& options) {
  const std::string target = WithoutTrailingSlash(dir);
  ReportSummary summary;
  ReplaceFolderAtomically(target, [&](const std::string& staging) {
    summary = WriteReport(dataset, result, staging, options);
  });
  summary.index_html = (fs::path(target) / "index.html").string();
  return summary;
}

}  // namespace handeye::tools
