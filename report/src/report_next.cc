// SPDX-License-Identifier: GPL-2.0-or-later
// The report's "what to capture next" section: `handeye advise`'s proposals
// (core/plan_advice.h) for the result's own capture.
#include <exception>
#include <ostream>
#include <string>

#include "handeye/core/transform.h"
#include "report_html.h"
#include "report_internal.h"

namespace handeye::report {

NextCapture AdviseNext(const Dataset& dataset, const CalibrationResult& result,
                       const ReportOptions& options) {
  NextCapture next;
  next.wanted = options.next_poses > 0;
  next.goal_mm = options.next_goal_mm;
  if (!next.wanted) return next;
  try {
    next.cell = PlanCellOfResult(dataset, result, std::nullopt);
    std::string why;
    if (!next.cell.Check(&why)) {
      next.why_not = "the result does not describe a cell to plan in: " + why;
      return next;
    }
    PlanOptions plan;
    plan.poses = options.next_poses;
    plan.goal_mm = options.next_goal_mm;
    next.advice = Advise(next.cell, RecordedPoses(dataset, result), plan);
  } catch (const std::exception& e) {
    next.why_not = e.what();
  }
  return next;
}

namespace {

void PredictedNow(const NextCapture& next, std::ostream& out) {
  out << "<table class=\"small\"><tr><th>camera</th><th>σ now, mm</th><th>from the views alone, "
         "mm</th><th>σ now, °</th></tr>\n";
  for (const auto& [name, sigma] : next.advice.now)
    out << "<tr><td>" << Escape(name) << "</td><td>" << Num(sigma.position_mm, 3) << "</td><td>"
        << Num(sigma.own_position_mm, 3) << "</td><td>" << Num(sigma.rotation_deg, 4)
        << "</td></tr>\n";
  out << "</table>\n<p>σ holds what the given intrinsics' uncertainty adds; more poses shrink only "
         "the part from the views, so the poses below are chosen for it. The rest shrinks with "
         "better intrinsics (<code>--refine-intrinsics</code>, or a new intrinsics "
         "calibration).</p>\n";
  if (next.goal_mm <= 0) return;
  if (next.advice.above_goal.empty()) {
    out << "<p>Every camera is predicted within the goal of " << Num(next.goal_mm, 3)
        << " mm.</p>\n";
    return;
  }
  out << "<p>Predicted above the goal of " << Num(next.goal_mm, 3) << " mm:";
  for (const std::string& name : next.advice.above_goal) out << " <b>" << Escape(name) << "</b>";
  out << ".</p>\n";
}

void ProposedPoses(const NextCapture& next, std::ostream& out) {
  const CapturePlan& plan = next.advice.next;
  out << "<table class=\"small\"><tr><th>pose</th><th>T_base_ee position, mm</th>"
         "<th>roll, pitch, yaw, °</th><th>seen by</th>";
  for (const PlanCamera& camera : next.cell.cameras)
    out << "<th>σ " << Escape(camera.camera.name) << ", mm</th>";
  out << "</tr>\n";
  for (const PlannedPose& pose : plan.poses) {
    const Eigen::Vector3d t = 1000.0 * pose.T_base_ee.translation();
    const Eigen::Vector3d rpy = RollPitchYaw(pose.T_base_ee.rotation()) * 180.0 / M_PI;
    std::string seen;
    for (const std::string& name : pose.cameras) seen += (seen.empty() ? "" : ", ") + name;
    out << "<tr><td>" << Escape(pose.id) << "</td><td>" << Num(t.x(), 1) << ", " << Num(t.y(), 1)
        << ", " << Num(t.z(), 1) << "</td><td>" << Num(rpy.x(), 1) << ", " << Num(rpy.y(), 1)
        << ", " << Num(rpy.z(), 1) << "</td><td>" << Escape(seen) << "</td>";
    for (const PlanCamera& camera : next.cell.cameras) {
      const auto sigma = pose.sigma_after.find(camera.camera.name);
      out << "<td>" << (sigma == pose.sigma_after.end() ? "" : Num(sigma->second.position_mm, 3))
          << "</td>";
    }
    out << "</tr>\n";
  }
  out << "</table>\n";
}

}  // namespace

void NextCaptureSection(const NextCapture& next, std::ostream& out) {
  if (!next.wanted) return;
  out << "<h2 id=\"next\">What to capture next</h2>\n";
  if (!next.why_not.empty()) {
    out << "<p>No advice: " << Escape(next.why_not) << "</p>\n";
    return;
  }
  out << "<p class=\"small\">Each camera's σ as the solve's noise model predicts it for the "
         "poses recorded, and the robot poses that would reduce the worst one most (in the "
         "region the recorded flange positions span, grown by 0.1 m), with the σ predicted "
         "once each is recorded. <code>handeye advise RESULT -o NEXT.json</code> writes the same "
         "poses for a robot program.</p>\n";
  PredictedNow(next, out);
  if (!next.advice.next.poses.empty()) ProposedPoses(next, out);
  if (!next.advice.next.failure.empty())
    out << "<p>" << Escape(next.advice.next.failure) << "</p>\n";
}

}  // namespace handeye::report
