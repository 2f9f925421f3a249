// SPDX-License-Identifier: GPL-2.0-or-later
// The names and checks of CalibrationOptions (core/src/calibration_options.cc):
// every method's name both ways, the --refine-intrinsics and --intrinsics-sigma
// syntax with what it refuses, and one refusal per rule of Check().
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "handeye/core/calibration.h"

using namespace handeye;

TEST_CASE("every method's name parses back to the method, and names are unique", "[options]") {
  const std::vector<std::string> names = MethodNames();
  CHECK(names.size() == 10);
  CHECK(std::set<std::string>(names.begin(), names.end()).size() == names.size());
  CHECK(names.front() == "joint");  // the default comes first in help texts
  for (const std::string& name : names) {
    const auto method = ParseMethod(name);
    REQUIRE(method);
    CHECK(std::string(MethodName(*method)) == name);
  }
  CHECK_FALSE(ParseMethod("Joint"));  // names are exact, as the CLI prints them
  CHECK_FALSE(ParseMethod("per_camera"));
  CHECK_FALSE(ParseMethod(""));
  CHECK(std::string(MethodName(static_cast<Method>(999))) == "unknown");
}

TEST_CASE("The --refine-intrinsics groups: each name, combinations, all, and what is refused",
          "[options]") {
  std::string why;
  CHECK(ParseIntrinsicsGroups("focal", &why) == unsigned{kFocal});
  CHECK(ParseIntrinsicsGroups("principal_point", &why) == unsigned{kPrincipalPoint});
  CHECK(ParseIntrinsicsGroups("distortion", &why) == unsigned{kDistortion});
  CHECK(ParseIntrinsicsGroups("focal,principal_point", &why) == unsigned{kFocal | kPrincipalPoint});
  CHECK(ParseIntrinsicsGroups("principal_point,focal,focal", &why) ==
        unsigned{kFocal | kPrincipalPoint});
  CHECK(ParseIntrinsicsGroups("all", &why) == unsigned{kAllIntrinsics});
  CHECK(ParseIntrinsicsGroups("focal,all", &why) == unsigned{kAllIntrinsics});

  CHECK_FALSE(ParseIntrinsicsGroups("focus", &why));
  CHECK(why == "expected focal, principal_point, distortion or all (comma-separated), got 'focus'");
  CHECK_FALSE(ParseIntrinsicsGroups("focal, principal_point", &why));  // no blanks
  CHECK(why.find("got ' principal_point'") != std::string::npos);
  CHECK_FALSE(ParseIntrinsicsGroups("focal,,distortion", &why));
  CHECK(why.find("got ''") != std::string::npos);
  CHECK_FALSE(ParseIntrinsicsGroups("", &why));
  CHECK(why.find("got nothing") != std::string::npos);
  CHECK_FALSE(ParseIntrinsicsGroups("FOCAL", nullptr));  // no reason asked: still refused
}

TEST_CASE(
    "The --intrinsics-sigma syntax: items, defaults for the items left out, 0, and what is refused",
    "[options]") {
  std::string why;
  const GivenIntrinsicsSigma defaults{1.0, 3.0};
  auto parsed = ParseIntrinsicsSigma("focal=0.5%,principal_point=2px", &why, defaults);
  REQUIRE(parsed);
  CHECK(parsed->focal_percent == 0.5);
  CHECK(parsed->principal_point_px == 2.0);
  parsed = ParseIntrinsicsSigma("principal_point=1.5px", &why, defaults);
  REQUIRE(parsed);
  CHECK(parsed->focal_percent == 1.0);  // left out: the default
  CHECK(parsed->principal_point_px == 1.5);
  parsed = ParseIntrinsicsSigma("focal=2%", &why, GivenIntrinsicsSigma{0.3, 7.0});
  REQUIRE(parsed);
  CHECK(parsed->focal_percent == 2.0);
  CHECK(parsed->principal_point_px == 7.0);  // the defaults given, not the library's
  parsed = ParseIntrinsicsSigma("focal=0%,principal_point=0px", &why, defaults);
  REQUIRE(parsed);
  CHECK(parsed->focal_percent == 0.0);
  parsed = ParseIntrinsicsSigma("0", &why, defaults);
  REQUIRE(parsed);
  CHECK(parsed->focal_percent == 0.0);
  CHECK(parsed->principal_point_px == 0.0);
  // The last item wins when one is given twice.
  parsed = ParseIntrinsicsSigma("focal=1%,focal=4%", &why, defaults);
  REQUIRE(parsed);
  CHECK(parsed->focal_percent == 4.0);

  for (const std::string bad :
       {"focal=1", "focal=1px", "principal_point=3", "principal_point=3%", "focal=-1%", "focal=%",
        "focal=1e999%", "focal=nan%", "focal=1 %", "focal", "focal=1%;principal_point=3px",
        "pp=3px", "", "00", "focal=1%%"}) {
    INFO("'" << bad << "'");
    why.clear();
    CHECK_FALSE(ParseIntrinsicsSigma(bad, &why, defaults));
    CHECK(why.find("expected focal=P% and/or principal_point=Npx") == 0);
  }
  ParseIntrinsicsSigma("focal=1%,principal_point=x px", &why, defaults);
  CHECK(why.find("got 'principal_point=x px'") != std::string::npos);  // names the bad item
}

TEST_CASE("IntrinsicsSigmaText writes what ParseIntrinsicsSigma reads", "[options]") {
  for (const GivenIntrinsicsSigma sigma :
       {GivenIntrinsicsSigma{1.0, 3.0}, GivenIntrinsicsSigma{0.25, 0.5},
        GivenIntrinsicsSigma{0, 0}}) {
    const std::string text = IntrinsicsSigmaText(sigma);
    std::string why;
    const auto back = ParseIntrinsicsSigma(text, &why, GivenIntrinsicsSigma{9, 9});
    INFO(text << ": " << why);
    REQUIRE(back);
    CHECK(back->focal_percent == sigma.focal_percent);
    CHECK(back->principal_point_px == sigma.principal_point_px);
  }
  CHECK(IntrinsicsSigmaText({1.0, 3.0}) == "focal=1%,principal_point=3px");
}

TEST_CASE("CalibrationOptions::Check takes the defaults and refuses each rule it states",
          "[options]") {
  std::string why;
  REQUIRE(CalibrationOptions{}.Check(&why));
  auto refused = [](CalibrationOptions options) {
    std::string reason;
    CHECK_FALSE(options.Check(&reason));
    CHECK_FALSE(options.Check(nullptr));  // no reason asked: the same answer
    return reason;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CalibrationOptions o;

  o = {};
  o.cauchy_scale_px = -1;
  CHECK(refused(o).find("cauchy_scale_px") == 0);
  o.cauchy_scale_px = nan;
  CHECK(refused(o).find("cauchy_scale_px") == 0);
  o.cauchy_scale_px = 0;  // 0: from the data
  CHECK(o.Check(&why));

  o = {};
  o.robot_sigma_mm = 1;  // the rotation's left at its default
  o.robot_sigma_deg = 0;
  CHECK(refused(o).find("robot_sigma_mm and robot_sigma_deg") == 0);
  o.robot_sigma_mm = -1;
  o.robot_sigma_deg = 0.1;
  CHECK(refused(o).find("robot_sigma_mm and robot_sigma_deg") == 0);
  o.robot_sigma_mm = inf;
  o.robot_sigma_deg = 0.1;
  CHECK(refused(o).find("robot_sigma_mm and robot_sigma_deg") == 0);
  for (const auto& [mm, deg] : {std::pair{0.1, 0.01}, std::pair{0.0, 0.0}, std::pair{-1.0, -1.0}}) {
    o.robot_sigma_mm = mm;
    o.robot_sigma_deg = deg;
    CHECK(o.Check(&why));
  }

  o = {};
  o.step_tolerance_mm = 0;
  CHECK(refused(o) == "step tolerances must be > 0");
  o = {};
  o.step_tolerance_deg = nan;
  CHECK(refused(o) == "step tolerances must be > 0");
  o = {};
  o.pnp_max_rms_px = inf;
  CHECK(refused(o) == "pnp_max_rms_px must be > 0");
  o = {};
  o.max_iterations = 0;
  CHECK(refused(o) == "max_iterations must be >= 1");
  o = {};
  o.threads = 0;
  CHECK(refused(o) == "threads must be >= 1");
  o = {};
  o.refine_intrinsics = kAllIntrinsics + 1;
  CHECK(refused(o).find("refine_intrinsics") == 0);

  // What only the joint method does.
  o = {};
  o.method = Method::kPark;
  CHECK(o.Check(&why));
  o.refine_intrinsics = kFocal;
  CHECK(refused(o).find("joint method only") != std::string::npos);
  o.refine_intrinsics = kNoIntrinsics;
  o.cross_validate = true;
  CHECK(refused(o).find("--cross-validate") == 0);
  o.cross_validate = false;
  o.fixed_cameras["cam0"] = Eigen::Isometry3d::Identity();
  CHECK(refused(o).find("held at given poses by the joint method only") != std::string::npos);
  o.method = Method::kJoint;
  CHECK(o.Check(&why));

  o = {};
  o.intrinsics_sigma.focal_percent = -0.5;
  CHECK(refused(o) == "intrinsics_sigma: finite and >= 0");
  o = {};
  o.intrinsics_sigma.principal_point_px = inf;
  CHECK(refused(o) == "intrinsics_sigma: finite and >= 0");

  o = {};
  o.warn.min_views_per_camera = -1;
  CHECK(refused(o) == "warn.min_views_per_camera must be >= 0");
  for (double QualityThresholds::*threshold :
       {&QualityThresholds::min_rotation_spread_deg, &QualityThresholds::min_axis_spread_deg,
        &QualityThresholds::max_camera_rms_px, &QualityThresholds::max_closed_form_disagreement_px})
    for (double bad : {-1.0, nan, inf}) {
      o = {};
      o.warn.*threshold = bad;
      CHECK(refused(o) == "warning thresholds must be finite and >= 0");
    }
}
