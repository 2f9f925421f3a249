// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Pieces of the report's HTML (report_html.cc writes the page,
// report_tables.cc the tables of poses, quality, uncertainty and pairs).

#include <Eigen/Geometry>
#include <sstream>
#include <string>

#include "report_internal.h"

namespace handeye::report {

/// Text with &, <, >, " and ' escaped for HTML.
std::string Escape(const std::string& text);
/// A number with `decimals` decimals in the same form in every locale
/// ("-1.25"), never "-0.00"; "n/a" for NaN and infinities.
std::string Num(double value, int decimals);
/// A tick label with just the decimals a tick step needs ("0.25", "10", "-3").
std::string TickLabel(double value, double step);
/// "x, y, z" with `decimals` decimals.
std::string Triple(const Eigen::Vector3d& v, int decimals);
/// "x, y, z, w" of a rotation's quaternion (w ≥ 0).
std::string Quaternion(const Eigen::Matrix3d& R);
/// A coloured square in the camera's colour.
std::string Swatch(int camera);

/// "What to capture next" (ReportOptions::next_poses); nothing when not wanted.
void NextCaptureSection(const NextCapture& next, std::ostream& out);

/// The tables of the page: camera poses and quality, uncertainty, refined
/// intrinsics, the shared transform and camera pairs.
void CameraTables(const ReportModel& model, std::ostringstream& out);
void UncertaintyTable(const ReportModel& model, std::ostringstream& out);
void IntrinsicsTable(const ReportModel& model, std::ostringstream& out);
void SharedAndPairs(const ReportModel& model, std::ostringstream& out);

}  // namespace handeye::report
