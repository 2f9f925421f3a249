// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/result_json.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "io_fixtures.h"
#include "support/test_support.h"

using namespace handeye;
using Catch::Matchers::Contains;

namespace {

CalibrationResult SampleJsonResult(Setup setup) {
  CalibrationResult r;
  r.setup = setup;
  r.method = Method::kJoint;
  CameraResult a;
  a.name = "cam0";
  a.calibrated = true;
  a.T_cam = MakeTransformFromRotationVector({0.3, -2.2, 0.1}, {1.9, -1.8, 1.9});
  a.rms_px = 0.19;
  a.views = 9;
  a.views_rejected = 1;
  PoseUncertainty sigma;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) sigma.covariance(i, j) = i == j ? 0.01 * (i + 1) : 0.001 * (i + j);
  sigma.position_mm = 0.245;
  sigma.rotation_deg = 0.0057;
  sigma.from_given_intrinsics = 0.5 * sigma.covariance;
  r.target_sigma = sigma;
  sigma.covariance_with_target = -0.25 * sigma.covariance.transpose();
  sigma.covariance_with_target->row(0).setConstant(0.125);  // not symmetric
  a.sigma = sigma;
  a.given_intrinsics_offset_px = Eigen::Vector4d(0.0, 0.0, -3.5, 1.25);
  IntrinsicsResult intrinsics;
  std::string why;
  intrinsics.camera = *Camera::Make("cam0", 1920, 1080, 1375.5, 1374.25, 959.5, 539.75, {-0.05, 0.01, 0, 0, 0}, &why);
  intrinsics.sigma[0] = 0.8;
  intrinsics.sigma[2] = 0.3;
  intrinsics.sigma[4] = 0.002;
  intrinsics.refined = {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2"};
  intrinsics.undetermined = {"k2"};
  a.intrinsics = intrinsics;
  CameraResult b;
  b.name = "cam1";
  b.calibrated = false;
  r.cameras = {a, b};
  r.T_target = MakeTransformFromRotationVector({0.1, 0.2, 0.3}, {0.01, 0.02, 0.1});
  CameraPairResult p;
  p.camera_k = "cam0";
  p.camera_t = "cam1";
  p.T_camk_camt = MakeTransformFromRotationVector({0.0, 1.5, 0.0}, {2.0, 0.0, 0.5});
  p.shared_views = 4;
  r.camera_pairs = {p};
  r.metrics = {0.18, 4.9, 0.21};
  r.solver.seconds = 0.12;
  r.solver.iterations = 6;
  r.solver.converged = true;
  r.solver.termination = "CONVERGENCE";
  r.solver.robot_sigma_mm = 0.25;
  r.solver.robot_sigma_deg = 0.0125;
  r.solver.robot_sigma_solved_mm = 0.125;
  r.solver.robot_sigma_solved_deg = 0.00625;
  ViewResult v;
  v.pose_id = "0001";
  v.camera = "cam0";
  v.num_points = 28;
  v.rms_px = 0.2;
  v.max_px = 0.5;
  ViewResult rejected = v;
  rejected.used = false;
  rejected.rejected_because = "fewer than 4 points";
  r.views = {v, rejected};
  Warning left_out = CameraWarning(WarningKind::kViewLeftOut, "cam0",
                                   "view of pose '0001' by camera 'cam0' left out: fewer than 4 points");
  left_out.pose = "0001";
  left_out.view = 1;
  r.warnings = {CameraWarning(WarningKind::kCameraNotSeen, "cam1", "camera 'cam1' never saw the target: not calibrated"),
                left_out};
  r.notes = {"initialised from ViSP on camera 'cam0'"};
  return r;
}

}  // namespace

TEST_CASE("Result files round trip exactly, both setups", "[result]") {
  const std::string dir = test::TempDir("result_round_trip");
  for (Setup setup : {Setup::kEyeToHand, Setup::kEyeInHand}) {
    const CalibrationResult r = SampleJsonResult(setup);
    const std::string path = dir + "/result.json";
    SaveResult(r, path);
    const std::string text = test::ReadText(path);
    CHECK(text.find(setup == Setup::kEyeToHand ? "\"T_base_cam\"" : "\"T_ee_cam\"") != std::string::npos);
    CHECK(text.find(setup == Setup::kEyeToHand ? "\"T_ee_target\"" : "\"T_base_target\"") != std::string::npos);
    CHECK(text.find("\"T_cam0_cam1\"") != std::string::npos);
    CHECK(text.find("NaN") == std::string::npos);
    const CalibrationResult back = LoadResult(path);
    REQUIRE(back.cameras.size() == 2);
    CHECK(back.cameras[0].T_cam.matrix() == r.cameras[0].T_cam.matrix());
    CHECK_FALSE(back.cameras[1].calibrated);
    CHECK(back.T_target.matrix() == r.T_target.matrix());
    REQUIRE(back.camera_pairs.size() == 1);
    CHECK(back.camera_pairs[0].T_camk_camt.matrix() == r.camera_pairs[0].T_camk_camt.matrix());
    CHECK(back.camera_pairs[0].shared_views == 4);
    CHECK(back.metrics.axzb_translation_mm == 4.9);
    CHECK(back.solver.iterations == 6);
    CHECK(back.solver.robot_sigma_mm == 0.25);
    CHECK(back.solver.robot_sigma_deg == 0.0125);
    CHECK(back.solver.robot_sigma_solved_mm == 0.125);
    CHECK(back.solver.robot_sigma_solved_deg == 0.00625);
    REQUIRE(back.views.size() == 2);
    CHECK(back.views[1].rejected_because == "fewer than 4 points");
    CHECK(back.warnings == r.warnings);
    CHECK(back.notes == r.notes);
    // Uncertainty and refined intrinsics, in the dataset's form.
    REQUIRE(back.cameras[0].sigma);
    CHECK(back.cameras[0].sigma->covariance == r.cameras[0].sigma->covariance);
    CHECK(back.cameras[0].sigma->from_given_intrinsics == r.cameras[0].sigma->from_given_intrinsics);
    REQUIRE(back.cameras[0].sigma->covariance_with_target);
    CHECK(*back.cameras[0].sigma->covariance_with_target ==
          *r.cameras[0].sigma->covariance_with_target);
    CHECK(back.cameras[0].sigma->position_mm == 0.245);
    // The views' own part, without what the given intrinsics add: half the
    // sample's covariance, whose position variances are 0.01, 0.02, 0.03.
    const auto written = nlohmann::json::parse(text)["cameras"]["cam0"]["sigma"];
    CHECK(written["own_position_mm"].get<double>() == Approx(std::sqrt(0.03)));
    CHECK(written["own_rotation_deg"].get<double>() ==
          Approx(std::sqrt(0.5 * (0.04 + 0.05 + 0.06))));
    REQUIRE(back.target_sigma);
    CHECK_FALSE(back.target_sigma->covariance_with_target);
    CHECK(back.target_sigma->from_given_intrinsics == r.target_sigma->from_given_intrinsics);
    CHECK(back.target_sigma->rotation_deg == 0.0057);
    CHECK_FALSE(back.cameras[1].sigma);
    REQUIRE(back.cameras[0].given_intrinsics_offset_px);
    CHECK(*back.cameras[0].given_intrinsics_offset_px == *r.cameras[0].given_intrinsics_offset_px);
    CHECK_FALSE(back.cameras[1].given_intrinsics_offset_px);
    REQUIRE(back.cameras[0].intrinsics);
    const IntrinsicsResult& in = *back.cameras[0].intrinsics;
    CHECK(in.camera.params == r.cameras[0].intrinsics->camera.params);
    CHECK(in.camera.width == 1920);
    CHECK(in.camera.num_distortion == 5);
    CHECK(in.sigma == r.cameras[0].intrinsics->sigma);
    CHECK(in.refined == r.cameras[0].intrinsics->refined);
    CHECK(in.undetermined == r.cameras[0].intrinsics->undetermined);
    CHECK(text.find("\"intrinsics_sigma\"") != std::string::npos);
    CHECK(text.find("\"position_mm\"") != std::string::npos);
  }
}

TEST_CASE("Broken result files are rejected with file and path", "[result]") {
  const std::string dir = test::TempDir("result_bad");
  const std::string path = dir + "/result.json";
  SaveResult(SampleJsonResult(Setup::kEyeToHand), path);
  const std::string good = test::ReadText(path);
  auto expect_error = [&](const std::string& text, const std::string& needle) {
    test::WriteText(path, text);
    try {
      LoadResult(path);
      FAIL("expected an InputError for " << needle);
    } catch (const InputError& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(path) != std::string::npos);
      CHECK(std::string(e.what()).find(needle) != std::string::npos);
    }
  };
  auto replace = [&](std::string from, std::string to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  expect_error(replace("handeye-result/1", "handeye-result/9"), "/format");
  expect_error(replace("\"joint\"", "\"magic\""), "/method");
  expect_error(replace("\"calibrated\": true", "\"calibrated\": 1"), "/cameras/cam0/calibrated");
  expect_error(replace("\"T_ee_target\": [", "\"T_ee_target_x\": ["), "/T_ee_target");
  expect_error(replace("\"kind\": \"camera_not_seen\"", "\"kind\": 3"), "/warning_details/0/kind");
  expect_error(replace("\"text\": \"camera 'cam1' never", "\"text\": \"camera 'cam2' never"),
               "/warning_details/0/text");
  CHECK_THROWS_AS(LoadResult(dir + "/missing.json"), InputError);
}

TEST_CASE("Result files carry each warning's text and its details, in one order", "[result]") {
  const std::string dir = test::TempDir("result_warnings");
  const std::string path = dir + "/result.json";
  SaveResult(SampleJsonResult(Setup::kEyeToHand), path);
  const nlohmann::json json = nlohmann::json::parse(test::ReadText(path));
  CHECK(json["warnings"] == nlohmann::json({"camera 'cam1' never saw the target: not calibrated",
                                            "view of pose '0001' by camera 'cam0' left out: fewer than 4 points"}));
  REQUIRE(json["warning_details"].size() == 2);
  const nlohmann::json& seen = json["warning_details"][0];
  CHECK(seen["kind"] == "camera_not_seen");
  CHECK(seen["camera"] == "cam1");
  CHECK(seen["pose"].is_null());
  CHECK(seen["view"].is_null());
  const nlohmann::json& view = json["warning_details"][1];
  CHECK(view["kind"] == "view_left_out");
  CHECK(view["pose"] == "0001");
  CHECK(view["view"] == 1);
  CHECK(view["text"] == json["warnings"][1]);

  // A file written before the details: its texts, of kind "other".
  nlohmann::json old = json;
  old.erase("warning_details");
  test::WriteText(path, old.dump());
  const CalibrationResult back = LoadResult(path);
  REQUIRE(back.warnings.size() == 2);
  CHECK(back.warnings[1].kind == WarningKind::kOther);
  CHECK(back.warnings[1].text == json["warnings"][1]);
  CHECK(back.warnings[1].camera.empty());
  CHECK_FALSE(back.warnings[1].view);

  // Details that do not match the texts one for one are refused.
  nlohmann::json short_details = json;
  short_details["warning_details"].erase(1);
  test::WriteText(path, short_details.dump());
  CHECK_THROWS_WITH(LoadResult(path), Contains("/warning_details") && Contains("one object per entry"));
}

TEST_CASE("Result files keep the diagnostics, the options and where they came from", "[result]") {
  const std::string dir = test::TempDir("result_diagnostics");
  CalibrationResult r = SampleJsonResult(Setup::kEyeInHand);
  CameraResult& cam = r.cameras[0];
  cam.max_px = 1.25;
  cam.outliers = 2;
  cam.axzb = {3.5, 0.75, 0.04, 9};
  cam.rotation_spread_deg = 41.5;
  cam.axis_spread_deg = 63.25;
  cam.closed_form = ClosedFormComparison{"park", true, "", 2.5, 0.125, 0.5};
  r.cameras[1].closed_form = ClosedFormComparison{"park", false, "park could not calibrate it: too few", 0, 0, 0};
  r.metrics.axzb_camera_translation_mm = 0.75;
  r.options.cross_terms = false;
  r.options.cauchy_scale_px = 2.5;
  r.options.intrinsics_sigma = GivenIntrinsicsSigma{0.5, 2.0};
  r.options.warn.min_views_per_camera = 6;
  r.handeye_version = "1.0.0";
  r.input = "cell/dataset.json";
  SaveResult(r, dir + "/result.json");
  const std::string text = test::ReadText(dir + "/result.json");
  CHECK(text.find("\"axzb_camera_frame\": \"ee\"") != std::string::npos);
  CHECK(text.find("\"frame\": \"ee\"") != std::string::npos);
  const CalibrationResult back = LoadResult(dir + "/result.json");
  const CameraResult& c = back.cameras[0];
  CHECK(c.max_px == 1.25);
  CHECK(c.outliers == 2);
  CHECK(c.axzb.target_frame_mm == 3.5);
  CHECK(c.axzb.camera_frame_mm == 0.75);
  CHECK(c.axzb.rotation_deg == 0.04);
  CHECK(c.axzb.views == 9);
  CHECK(c.rotation_spread_deg == 41.5);
  CHECK(c.axis_spread_deg == 63.25);
  REQUIRE(c.closed_form);
  CHECK(c.closed_form->available);
  CHECK(c.closed_form->displacement_px == 0.5);
  CHECK(back.metrics.axzb_camera_translation_mm == 0.75);
  CHECK_FALSE(back.cameras[1].closed_form);  // not calibrated: no diagnostics written
  CHECK_FALSE(back.options.cross_terms);
  CHECK(back.options.cauchy_scale_px == 2.5);
  CHECK(back.options.intrinsics_sigma.focal_percent == 0.5);
  CHECK(back.options.intrinsics_sigma.principal_point_px == 2.0);
  CHECK(back.options.warn.min_views_per_camera == 6);
  CHECK(back.options.method == Method::kJoint);
  CHECK(back.handeye_version == "1.0.0");
  CHECK(back.input == "cell/dataset.json");
}
