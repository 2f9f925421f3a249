// SPDX-License-Identifier: GPL-2.0-or-later
// A solution's camera against a closed form on the camera's own views, and
// what a disagreement between them points at (diagnostics_internal.h).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "closed_form.h"
#include "diagnostics_internal.h"
#include "problem.h"

namespace handeye::internal {

std::string AuthorName(std::string method) {
  if (method == "visp") return "ViSP";
  if (!method.empty())
    method[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(method[0])));
  return method;
}

namespace {

// Mean image displacement of camera k's target points (placed by the chain
// T_cam_mount · T_mount_holder[j] · T_holder_target) when seen from
// T_cam_mount_other instead.
double DisplacementPx(const Problem& problem, int k, const Eigen::Isometry3d& T_cam_mount,
                      const Eigen::Isometry3d& T_holder_target,
                      const Eigen::Isometry3d& T_cam_mount_other) {
  const Camera& camera = problem.dataset->cameras[k];
  double sum = 0;
  int n = 0;
  for (int v : problem.camera_views[k]) {
    const View& view = problem.views[v];
    const Eigen::Isometry3d T_cam_target =
        T_cam_mount * problem.T_mount_holder[view.pose] * T_holder_target;
    const Eigen::Isometry3d T_othercam_target =
        T_cam_mount_other * problem.T_mount_holder[view.pose] * T_holder_target;
    for (const Eigen::Vector3d& p : view.p_target) {
      const auto uv = camera.Project(T_cam_target * p);
      const auto uv_other = camera.Project(T_othercam_target * p);
      if (!uv || !uv_other) continue;
      sum += (*uv_other - *uv).norm();
      ++n;
    }
  }
  return n ? sum / n : 0.0;
}

/// OpenCV's closed forms pair every two views of a camera, so their cost
/// grows with the square of its views: a camera of 500 views took 2.5 s a
/// method, most of a calibration of 2 cameras and 1000 poses. The comparison
/// takes the kClosedFormViews views of most diverse rotation
/// (WithDiverseViews); no camera of METRIC's medium cell has more (119).
constexpr size_t kClosedFormViews = 150;

/// Camera k of `problem` alone, with at most kClosedFormViews of its views
/// (all of them, in their order, where it has no more).
Problem ClosedFormViewsOf(const Problem& problem, int k) {
  Problem one;
  one.dataset = problem.dataset;
  one.T_mount_holder = problem.T_mount_holder;
  one.camera_views.resize(problem.camera_views.size());
  for (int v : problem.camera_views[k]) {
    one.camera_views[k].push_back(static_cast<int>(one.views.size()));
    one.views.push_back(problem.views[v]);
  }
  return one.camera_views[k].size() > kClosedFormViews ? WithDiverseViews(one, kClosedFormViews)
                                                       : one;
}

}  // namespace

ClosedFormComparison CompareWithClosedForm(const Problem& all_views, int k,
                                           const Eigen::Isometry3d& T_cam_mount,
                                           const Eigen::Isometry3d& T_holder_target,
                                           Method method) {
  const Problem problem = ClosedFormViewsOf(all_views, k);
  ClosedFormComparison cmp;
  cmp.method = MethodName(method);
  std::string why;
  const auto closed = ClosedFormHandEye(problem, k, method, &why);
  if (!closed) {
    cmp.why_not = cmp.method + " could not calibrate it: " + why;
    return cmp;
  }
  cmp.available = true;
  const Eigen::Isometry3d& T_cam_mount_closed_form = closed->first;
  // The camera poses as the result states them (T_mount_cam), so that the
  // figures are those `evaluate` gives with the closed form as the truth.
  const PoseDifference moved =
      DifferenceOf(T_cam_mount_closed_form.inverse(), T_cam_mount.inverse());
  cmp.translation_mm = moved.translation_mm;
  cmp.rotation_deg = moved.rotation_deg;
  // The same target points (placed by the result's chain) seen from the
  // closed form's camera pose. Each method's own chain would not do: a closed
  // form's error in T_cam_mount is largely made up by its own
  // T_holder_target, so its predictions agree while the camera poses do not.
  cmp.displacement_px =
      DisplacementPx(problem, k, T_cam_mount, T_holder_target, T_cam_mount_closed_form);
  return cmp;
}

// What a disagreement with the closed form points at, by the other closed
// forms (Park, Tsai, ViSP; not the compared one, nor the result's own
// method). Closed forms scatter by pixels on a real robot's poses (13 px
// between Park's and ViSP's on the set below), so "agree" is relative: within
// the warning's threshold or a tenth of the disagreement, but never beyond 20
// thresholds (a camera put metres off projects points near its own plane,
// where displacements run to 10¹² px and a tenth of them means nothing). Where another closed form
// agrees with the result, the compared one is the odd one out (on the industrial_calibration
// ChArUco set Tsai's rotation axes put the camera 657 mm off while Park's and ViSP's agree within
// 15 px): neither the robot poses nor the result are in question. Where the closed forms agree with
// each other but not with the result, the result is. Else empty: the closed forms disagree among
// themselves too, and the data are in question.
std::string DisagreementCause(const Problem& all_views, int k, const Eigen::Isometry3d& T_cam_mount,
                              const Eigen::Isometry3d& T_holder_target, Method result_method,
                              const ClosedFormComparison& compared, double threshold_px) {
  const Problem problem = ClosedFormViewsOf(all_views, k);
  const double agree_px =
      std::max(threshold_px, std::min(0.1 * compared.displacement_px, 20.0 * threshold_px));
  std::string why;
  std::vector<std::string> others;
  std::vector<Eigen::Isometry3d> other_T_cam_mount;
  std::string closest;
  double closest_px = std::numeric_limits<double>::infinity();
  for (const NamedClosedForm& other : SilentClosedForms(problem, k, &why)) {
    if (other.method == compared.method || other.method == MethodName(result_method)) continue;
    others.push_back(AuthorName(other.method));
    other_T_cam_mount.push_back(other.T_cam_mount);
    const double px = DisplacementPx(problem, k, T_cam_mount, T_holder_target, other.T_cam_mount);
    if (px < closest_px) {
      closest_px = px;
      closest = AuthorName(other.method);
    }
  }
  const std::string name = AuthorName(compared.method) + "'s closed form";
  if (closest_px <= agree_px)
    return name +
           (compared.displacement_px > 100.0 * threshold_px ? " failed on these views"
                                                            : " is the odd one out") +
           ": " + closest + "'s agrees with the result within " + Fixed(closest_px, 1) +
           " px, so neither the robot poses nor the result are in question";
  if (others.empty()) return "";
  // The compared closed form against the others, the points placed by its
  // own chain (the result's may be the one that failed).
  const auto compared_form = ClosedFormHandEye(problem, k, *ParseMethod(compared.method), &why);
  if (!compared_form) return "";
  for (const Eigen::Isometry3d& other : other_T_cam_mount)
    if (DisplacementPx(problem, k, compared_form->first, compared_form->second, other) > agree_px)
      return "";
  auto names = [](const std::vector<std::string>& list) {
    std::string out;
    for (size_t i = 0; i < list.size(); ++i)
      out += (i == 0 ? "" : i + 1 == list.size() ? " and " : ", ") + list[i];
    return out;
  };
  others.insert(others.begin(), AuthorName(compared.method));
  const std::string agreeing =
      "the closed forms of " + names(others) + " agree with each other but not with the result: ";
  if (result_method != Method::kJoint && result_method != Method::kPerCamera)
    return agreeing + AuthorName(MethodName(result_method)) +
           "'s closed form (the result) failed on these views, not the robot; use --method joint";
  return agreeing +
         "the solve, not the robot, is the odd one out (another minimum, or this camera's views at "
         "odds with the other cameras'); compare with --method per-camera";
}

}  // namespace handeye::internal
