// SPDX-License-Identifier: GPL-2.0-or-later
// The names and checks of CalibrationOptions: methods, intrinsics groups.
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "handeye/core/calibration.h"

namespace handeye {
namespace {

struct MethodEntry {
  Method method;
  const char* name;
};
constexpr MethodEntry kMethods[] = {
    {Method::kJoint, "joint"},
    {Method::kPerCamera, "per-camera"},
    {Method::kTsai, "tsai"},
    {Method::kPark, "park"},
    {Method::kHoraud, "horaud"},
    {Method::kAndreff, "andreff"},
    {Method::kDaniilidis, "daniilidis"},
    {Method::kShah, "shah"},
    {Method::kLi, "li"},
    {Method::kVisp, "visp"},
};

}  // namespace

const char* MethodName(Method method) {
  for (const auto& m : kMethods)
    if (m.method == method) return m.name;
  return "unknown";
}

std::optional<Method> ParseMethod(const std::string& name) {
  for (const auto& m : kMethods)
    if (name == m.name) return m.method;
  return std::nullopt;
}

std::vector<std::string> MethodNames() {
  std::vector<std::string> names;
  for (const auto& m : kMethods) names.push_back(m.name);
  return names;
}

std::optional<unsigned> ParseIntrinsicsGroups(const std::string& list, std::string* why) {
  unsigned groups = kNoIntrinsics;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item == "focal")
      groups |= kFocal;
    else if (item == "principal_point")
      groups |= kPrincipalPoint;
    else if (item == "distortion")
      groups |= kDistortion;
    else if (item == "all")
      groups |= kAllIntrinsics;
    else {
      if (why)
        *why = "expected focal, principal_point, distortion or all (comma-separated), got '" +
               item + "'";
      return std::nullopt;
    }
  }
  if (groups == kNoIntrinsics) {
    if (why)
      *why = "expected focal, principal_point, distortion or all (comma-separated), got nothing";
    return std::nullopt;
  }
  return groups;
}

std::optional<GivenIntrinsicsSigma> ParseIntrinsicsSigma(const std::string& text, std::string* why,
                                                         const GivenIntrinsicsSigma& defaults) {
  static const char* kExpected =
      "expected focal=P% and/or principal_point=Npx (comma-separated), or 0 (the given intrinsics exact)";
  auto fail = [&](const std::string& got) -> std::optional<GivenIntrinsicsSigma> {
    if (why) *why = std::string(kExpected) + ", got '" + got + "'";
    return std::nullopt;
  };
  if (text == "0") return GivenIntrinsicsSigma{0.0, 0.0};
  GivenIntrinsicsSigma sigma = defaults;
  std::stringstream in(text);
  std::string item;
  bool any = false;
  while (std::getline(in, item, ',')) {
    const auto equals = item.find('=');
    if (equals == std::string::npos) return fail(item);
    const std::string key = item.substr(0, equals), value = item.substr(equals + 1);
    const std::string unit = key == "focal" ? "%" : key == "principal_point" ? "px" : "";
    if (unit.empty() || value.size() <= unit.size() ||
        value.compare(value.size() - unit.size(), unit.size(), unit) != 0)
      return fail(item);
    const std::string number = value.substr(0, value.size() - unit.size());
    char* end = nullptr;
    const double v = std::strtod(number.c_str(), &end);
    if (end != number.c_str() + number.size() || !std::isfinite(v) || v < 0) return fail(item);
    (key == "focal" ? sigma.focal_percent : sigma.principal_point_px) = v;
    any = true;
  }
  if (!any) return fail(text);
  return sigma;
}

std::string IntrinsicsSigmaText(const GivenIntrinsicsSigma& sigma) {
  std::ostringstream out;
  out << "focal=" << sigma.focal_percent << "%,principal_point=" << sigma.principal_point_px << "px";
  return out.str();
}

bool CalibrationOptions::Check(std::string* why) const {
  auto fail = [why](const char* reason) {
    if (why) *why = reason;
    return false;
  };
  if (!(cauchy_scale_px >= 0) || !std::isfinite(cauchy_scale_px))
    return fail("cauchy_scale_px must be > 0 (or 0: from the data)");
  if (!std::isfinite(robot_sigma_mm) || !std::isfinite(robot_sigma_deg) ||
      (robot_sigma_mm < 0) != (robot_sigma_deg < 0) ||
      (robot_sigma_mm == 0) != (robot_sigma_deg == 0))
    return fail(
        "robot_sigma_mm and robot_sigma_deg: both > 0, both 0 (exact robot) or both < 0 "
        "(estimated)");
  if (!(step_tolerance_mm > 0) || !(step_tolerance_deg > 0))
    return fail("step tolerances must be > 0");
  if (!(pnp_max_rms_px > 0) || !std::isfinite(pnp_max_rms_px))
    return fail("pnp_max_rms_px must be > 0");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (threads < 1) return fail("threads must be >= 1");
  if (refine_intrinsics > kAllIntrinsics) return fail("refine_intrinsics: IntrinsicsGroup flags");
  if (refine_intrinsics != kNoIntrinsics && method != Method::kJoint)
    return fail("intrinsics are refined by the joint method only (--method joint)");
  if (!(intrinsics_sigma.focal_percent >= 0) || !std::isfinite(intrinsics_sigma.focal_percent) ||
      !(intrinsics_sigma.principal_point_px >= 0) || !std::isfinite(intrinsics_sigma.principal_point_px))
    return fail("intrinsics_sigma: finite and >= 0");
  if (warn.min_views_per_camera < 0) return fail("warn.min_views_per_camera must be >= 0");
  for (double v : {warn.min_rotation_spread_deg, warn.min_axis_spread_deg, warn.max_camera_rms_px,
                   warn.max_closed_form_disagreement_px})
    if (!std::isfinite(v) || v < 0) return fail("warning thresholds must be finite and >= 0");
  if (cross_validate && method != Method::kJoint)
    return fail(
        "--cross-validate: the held-out validation runs with the joint method only (--method "
        "joint)");
  if (!fixed_cameras.empty() && method != Method::kJoint)
    return fail("cameras are held at given poses by the joint method only (--method joint)");
  return true;
}

}  // namespace handeye
