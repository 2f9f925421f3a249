// SPDX-License-Identifier: GPL-2.0-or-later
// The calibration report: files of a rendered 4-camera cell, marks at the
// right pixels in the overlays (read back from the PNGs), warnings, and
// results that do not belong to the dataset.
#include "handeye/report/report.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <set>

#include "handeye/core/checkerboard.h"
#include "handeye/core/diagnostics.h"
#include "handeye/core/error.h"
#include "handeye/io/result_json.h"
#include "handeye/sim/simulation.h"
#include "handeye/sim/synthetic.h"
#include "io/io_fixtures.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Catch::Matchers::Contains;
namespace fs = std::filesystem;

// A small eye-to-hand cell, 4 cameras, optionally rendered to PNG.
struct Cell {
  SyntheticScene scene;
  CalibrationResult result;
};

Cell MakeCell(Setup setup, int poses, const std::string& render_dir) {
  SceneOptions options;
  options.cell = "small";
  options.setup = setup;
  options.num_cameras = 4;
  options.num_poses = poses;
  options.seed = 11;
  options.width = 960;
  options.height = 540;
  Cell cell;
  cell.scene = MakeScene(options, std::make_shared<const CheckerboardTarget>(7, 4, 0.04));
  if (!render_dir.empty()) {
    RenderOptions render;
    render.supersampling = 2;  // the images are a backdrop here, not measured
    WriteSimulation(&cell.scene, render, render_dir, 2);
  }
  std::mt19937_64 rng(5);
  AddProjectedObservations(&cell.scene, 0.1, &rng);
  cell.result = Calibrate(cell.scene.dataset, CalibrationOptions{});
  return cell;
}

// Every local file the page links to (img src and a href).
std::vector<std::string> LinkedFiles(const std::string& html) {
  std::vector<std::string> files;
  const std::regex link(R"((?:src|href)=\"([^\"#:]+)\")");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), link); it != std::sregex_iterator();
       ++it)
    files.push_back((*it)[1]);
  return files;
}

// Weighted centroid, around `centre` within `radius` pixels, of how much each
// pixel looks like a pure colour with channels `hi_a` and `hi_b` high and
// `lo` low (BGR indices): min(hi) − lo − |hi_a − hi_b|, which is 0 for grey,
// α·255 for the colour blended over grey with coverage α, and ≤ 0 for every
// other colour the overlay draws near points.
std::optional<Eigen::Vector2d> ColourCentroid(const cv::Mat& image, const Eigen::Vector2d& centre,
                                              double radius, int hi_a, int hi_b, int lo) {
  double sum_w = 0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  const int r = static_cast<int>(std::ceil(radius));
  const int u0 = static_cast<int>(std::lround(centre.x())),
            v0 = static_cast<int>(std::lround(centre.y()));
  for (int v = v0 - r; v <= v0 + r; ++v)
    for (int u = u0 - r; u <= u0 + r; ++u) {
      if (u < 0 || v < 0 || u >= image.cols || v >= image.rows) return std::nullopt;
      if (Eigen::Vector2d(u - centre.x(), v - centre.y()).norm() > radius) continue;
      const cv::Vec3b px = image.at<cv::Vec3b>(v, u);
      const double w = std::min(px[hi_a], px[hi_b]) - px[lo] - std::abs(px[hi_a] - px[hi_b]);
      if (w <= 0) continue;
      sum_w += w;
      sum += w * Eigen::Vector2d(u, v);
    }
  if (sum_w < 255) return std::nullopt;  // less than one pixel's worth of the colour
  return sum / sum_w;
}

// Nearest-neighbour distance of each detected point.
std::vector<double> NearestNeighbour(const std::vector<Eigen::Vector2d>& points) {
  std::vector<double> out;
  for (size_t i = 0; i < points.size(); ++i) {
    double best = 1e9;
    for (size_t j = 0; j < points.size(); ++j)
      if (j != i) best = std::min(best, (points[i] - points[j]).norm());
    out.push_back(best);
  }
  return out;
}

TEST_CASE("report of a rendered 4-camera cell: files, links and marks at the right pixels",
          "[report]") {
  const std::string dir = test::TempDir("report_cell");
  const Cell cell = MakeCell(Setup::kEyeToHand, 8, dir + "/sim");
  const Dataset& dataset = cell.scene.dataset;
  ReportOptions options;
  options.threads = 2;
  const ReportSummary summary = WriteReport(dataset, cell.result, dir + "/report", options);
  REQUIRE(summary.overlays == static_cast<int>(dataset.observations.size()));

  const std::string html = test::ReadText(dir + "/report/index.html");
  REQUIRE(!html.empty());
  CHECK_THAT(html, Contains("T_base_cam") && Contains("T_ee_target") && Contains("T_cam0_cam1"));
  CHECK(html.find("<script") == std::string::npos);
  // Every linked file exists and decodes; every overlay and thumbnail is linked.
  const auto linked = LinkedFiles(html);
  int overlays = 0, thumbs = 0, plots = 0;
  for (const auto& file : linked) {
    INFO(file);
    const cv::Mat image = cv::imread(dir + "/report/" + file);
    CHECK(!image.empty());
    overlays += file.rfind("overlays/", 0) == 0;
    thumbs += file.rfind("thumbs/", 0) == 0;
    plots += file.rfind("plots/", 0) == 0;
  }
  // Worst 10 views appear twice (first in the worst list, then per camera).
  const int views = static_cast<int>(dataset.observations.size());
  CHECK(overlays == views + std::min(views, 10));
  CHECK(thumbs == views + std::min(views, 10));
  CHECK(plots == 2 * 4 + 2);  // histogram and image plane per camera, view RMS, map

  // The overlays: rings at the detected pixels and crosses at the pixels
  // predicted through the calibrated chain, to a fraction of a pixel (an
  // error in the pixel-centre convention would show as 0.5 px).
  int rings = 0, crosses = 0;
  double worst_ring = 0, worst_cross = 0;
  for (const Observation& obs : dataset.observations) {
    const int k = dataset.CameraIndex(obs.camera);
    const int j = dataset.PoseIndex(obs.pose_id);
    const Camera& camera = dataset.cameras[k];
    const std::string path = dir + "/report/overlays/" + obs.camera + "/" + obs.pose_id + ".png";
    const cv::Mat overlay = cv::imread(path, cv::IMREAD_COLOR);
    REQUIRE(overlay.cols == camera.width);
    REQUIRE(overlay.rows == camera.height);
    const Eigen::Isometry3d T_cam_target =
        cell.result.cameras[k].T_cam.inverse() * dataset.poses[j].T_base_ee * cell.result.T_target;
    const auto spacing = NearestNeighbour(obs.points_px);
    for (size_t i = 0; i < obs.ids.size(); ++i) {
      const Eigen::Vector2d& detected = obs.points_px[i];
      // Clear of the header band and the legend panel (bottom left).
      if (detected.y() < 0.12 * camera.height) continue;
      if (detected.x() < 0.5 * camera.width && detected.y() > 0.55 * camera.height) continue;
      if (spacing[i] < 12) continue;  // marks of neighbours would share the window
      const auto ring =
          ColourCentroid(overlay, detected, 0.45 * spacing[i], 0, 1, 2);  // cyan: B, G high
      REQUIRE(ring);
      worst_ring = std::max(worst_ring, (*ring - detected).norm());
      ++rings;
      const auto predicted =
          camera.Project(T_cam_target * dataset.target->FindPoint(obs.ids[i])->p_target);
      REQUIRE(predicted);
      const auto cross =
          ColourCentroid(overlay, *predicted, 0.3 * spacing[i], 0, 2, 1);  // magenta: B, R high
      REQUIRE(cross);
      worst_cross = std::max(worst_cross, (*cross - *predicted).norm());
      ++crosses;
    }
  }
  INFO("rings " << rings << " worst " << worst_ring << " px; crosses " << crosses << " worst "
                << worst_cross);
  CHECK(rings > 100);
  CHECK(worst_ring < 0.2);
  CHECK(worst_cross < 0.2);
}

TEST_CASE("report shows the warnings of a camera whose result disagrees with its closed form", "[report]") {
  const std::string dir = test::TempDir("report_warnings");
  Cell cell = MakeCell(Setup::kEyeToHand, 12, "");
  ReportOptions options;
  options.threads = 1;
  {
    const ReportSummary good = WriteReport(cell.scene.dataset, cell.result, dir + "/good", options);
    for (const auto& w : good.warnings) {
      INFO(w);
      CHECK(w.find("disagree") == std::string::npos);
      CHECK(w.find("large residuals") == std::string::npos);
    }
  }
  // Move cam2 by 8 cm: its reprojection error and its distance to the closed
  // form (which does not know about the change) both become large. The
  // diagnostics are the core's (Diagnose); the report shows what they say.
  cell.result.cameras[2].T_cam.translation() += Eigen::Vector3d(0.08, 0, 0);
  cell.result.warnings = Diagnose(cell.scene.dataset, CalibrationOptions{}, &cell.result);
  const ReportSummary bad = WriteReport(cell.scene.dataset, cell.result, dir + "/bad", options);
  CHECK(bad.warnings == cell.result.warnings);
  std::string all;
  for (const auto& w : bad.warnings) all += w + "\n";
  INFO(all);
  CHECK_THAT(all, Contains("camera 'cam2': large residuals"));
  CHECK_THAT(all, Contains("camera 'cam2': the result and Park's per-camera closed form disagree"));
  CHECK(all.find("camera 'cam1': the result") == std::string::npos);
  CHECK_THAT(test::ReadText(dir + "/bad/index.html"), Contains("disagree"));
}

TEST_CASE("report's warnings are result.json's, on a cell that triggers several", "[report]") {
  const std::string dir = test::TempDir("report_same_warnings");
  const Cell cell = MakeCell(Setup::kEyeToHand, 8, "");
  CalibrationOptions strict;
  strict.warn.max_camera_rms_px = 0.01;  // 0.1 px noise: every camera is "large"
  const CalibrationResult result = Calibrate(cell.scene.dataset, strict);
  SaveResult(result, dir + "/result.json");
  const nlohmann::json json = nlohmann::json::parse(test::ReadText(dir + "/result.json"));
  const std::vector<std::string> written = json["warnings"];
  int few_views = 0, large = 0;
  for (const auto& w : written) {
    few_views += w.find("few views") != std::string::npos ? 1 : 0;
    large += w.find("large residuals") != std::string::npos ? 1 : 0;
  }
  CHECK(few_views >= 2);
  CHECK(large >= 2);
  ReportOptions options;
  options.threads = 1;
  const ReportSummary summary = WriteReport(cell.scene.dataset, LoadResult(dir + "/result.json"), dir, options);
  CHECK(summary.warnings == written);
  // The figures are the result's, not recomputed: a changed one is shown as it is.
  CalibrationResult marked = result;
  REQUIRE(marked.cameras[0].closed_form);
  marked.cameras[0].closed_form->displacement_px = 123.456;
  WriteReport(cell.scene.dataset, marked, dir + "/marked", options);
  CHECK_THAT(test::ReadText(dir + "/marked/index.html"), Contains("123.46"));
}

TEST_CASE("report rotation-diversity warning follows the camera's robot motions", "[report]") {
  const Cell cell = MakeCell(Setup::kEyeToHand, 12, "");
  const Dataset& dataset = cell.scene.dataset;
  // cam0's largest rotation between two of its poses, computed here.
  std::vector<int> poses;
  for (const auto& obs : dataset.observations)
    if (obs.camera == "cam0") poses.push_back(dataset.PoseIndex(obs.pose_id));
  double spread_deg = 0;
  for (int a : poses)
    for (int b : poses)
      spread_deg = std::max(spread_deg, RotationDistance(dataset.poses[a].T_base_ee.rotation(),
                                                         dataset.poses[b].T_base_ee.rotation()) *
                                            180.0 / M_PI);
  REQUIRE(spread_deg > 1);
  CalibrationOptions options;
  options.compare_closed_form = false;
  options.warn.min_axis_spread_deg = 0;
  auto has_warning = [&](double threshold) {
    options.warn.min_rotation_spread_deg = threshold;
    CalibrationResult result = cell.result;
    for (const auto& w : Diagnose(dataset, options, &result))
      if (w.rfind("camera 'cam0': poor rotation diversity", 0) == 0) return true;
    return false;
  };
  CHECK(has_warning(spread_deg + 0.01));
  CHECK_FALSE(has_warning(spread_deg - 0.01));
}

TEST_CASE("report of an eye-in-hand cell without images", "[report]") {
  const std::string dir = test::TempDir("report_eye_in_hand");
  const Cell cell = MakeCell(Setup::kEyeInHand, 8, "");
  ReportOptions options;
  options.threads = 2;
  const ReportSummary summary = WriteReport(cell.scene.dataset, cell.result, dir, options);
  CHECK(summary.overlays == static_cast<int>(cell.scene.dataset.observations.size()));
  CHECK_THAT(test::ReadText(dir + "/index.html"),
             Contains("T_ee_cam") && Contains("T_base_target"));
  const cv::Mat map = cv::imread(dir + "/plots/map.png");
  CHECK(!map.empty());
  // No images: the overlays are drawn on a neutral canvas of the camera's size.
  const Observation& first = cell.scene.dataset.observations.front();
  const cv::Mat overlay =
      cv::imread(dir + "/overlays/" + first.camera + "/" + first.pose_id + ".png");
  CHECK(overlay.cols == cell.scene.dataset.cameras[0].width);
}

TEST_CASE("report refuses a result of another dataset", "[report]") {
  const std::string dir = test::TempDir("report_mismatch");
  Cell cell = MakeCell(Setup::kEyeToHand, 8, "");
  CalibrationResult renamed = cell.result;
  renamed.cameras[1].name = "camX";
  CHECK_THROWS_AS(WriteReport(cell.scene.dataset, renamed, dir), InputError);
  CHECK_THROWS_WITH(WriteReport(cell.scene.dataset, renamed, dir),
                    Contains("cam1") && Contains("another dataset"));
  CalibrationResult other_setup = cell.result;
  other_setup.setup = Setup::kEyeInHand;
  CHECK_THROWS_WITH(WriteReport(cell.scene.dataset, other_setup, dir), Contains("setup"));
  CHECK_FALSE(fs::exists(dir + "/index.html"));
}

}  // namespace
}  // namespace handeye
