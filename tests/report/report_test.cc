// SPDX-License-Identifier: GPL-2.0-or-later
// The calibration report: files of a rendered 4-camera cell, marks at the
// right pixels in the overlays (read back from the PNGs), the plots as inline
// SVG (escaped text, no NaN), warnings, and results that do not belong to the
// dataset.
#include "handeye/report/report.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <limits>
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

// `cam1_name`, when given, renames camera 1 before the calibration.
Cell MakeCell(Setup setup, int poses, const std::string& render_dir,
              const std::string& cam1_name = "") {
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
  if (!cam1_name.empty()) {
    Dataset& dataset = cell.scene.dataset;
    const std::string old_name = dataset.cameras[1].name;
    dataset.cameras[1].name = cam1_name;
    for (Observation& obs : dataset.observations)
      if (obs.camera == old_name) obs.camera = cam1_name;
    for (RobotPose& pose : dataset.poses) {
      const auto image = pose.images.find(old_name);
      if (image == pose.images.end()) continue;
      pose.images[cam1_name] = image->second;
      pose.images.erase(old_name);
    }
  }
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

// The inline SVG elements of the page, each from "<svg" to its "</svg>".
std::vector<std::string> SvgElements(const std::string& html) {
  std::vector<std::string> out;
  for (size_t at = html.find("<svg xmlns="); at != std::string::npos;
       at = html.find("<svg xmlns=", at + 1)) {
    // Nested <svg> (the clipped data area) closes before the outer one.
    size_t end = at;
    for (int depth = 0;;) {
      const size_t open = html.find("<svg", end + 1), close = html.find("</svg>", end + 1);
      if (close == std::string::npos) return out;
      if (open < close) {
        ++depth;
        end = open;
      } else if (depth-- == 0) {
        out.push_back(html.substr(at, close + 6 - at));
        break;
      } else {
        end = close;
      }
    }
  }
  return out;
}

// Whether `xml` is well formed as far as a browser's parser cares: tags
// nest and close, no attribute twice in a tag, no raw '<' or '&' in text or
// attribute values (only the five entities the writer uses).
bool WellFormed(const std::string& xml, std::string* why) {
  std::vector<std::string> open;
  const std::regex tag(R"(<(/?)([a-zA-Z]+)((?:\s+[a-zA-Z:-]+="[^"<]*")*)\s*(/?)>)");
  const std::regex entity(R"(&(amp|lt|gt|quot|#39);)");
  size_t at = 0;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), tag); it != std::sregex_iterator();
       ++it) {
    const std::string text = xml.substr(at, it->position() - at) + (*it)[3].str();
    if (text.find('<') != std::string::npos ||
        std::regex_replace(text, entity, "").find('&') != std::string::npos) {
      *why = "raw < or & near: " + text.substr(0, 80);
      return false;
    }
    at = it->position() + it->length();
    const std::string attributes = (*it)[3];
    const std::regex name(R"(([a-zA-Z:-]+)=")");
    std::set<std::string> names;
    for (auto a = std::sregex_iterator(attributes.begin(), attributes.end(), name);
         a != std::sregex_iterator(); ++a)
      if (!names.insert((*a)[1]).second) {
        *why = "attribute " + (*a)[1].str() + " twice in <" + (*it)[2].str() + ">";
        return false;
      }
    if ((*it)[4].length()) continue;  // <x ... />
    if ((*it)[1].length() == 0) {
      open.push_back((*it)[2]);
    } else if (open.empty() || open.back() != (*it)[2]) {
      *why = "unbalanced </" + (*it)[2].str() + ">";
      return false;
    } else {
      open.pop_back();
    }
  }
  *why = open.empty() ? "" : "unclosed <" + open.back() + ">";
  return open.empty() && at == xml.size();
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
  // The plots are inline SVG, not image files: histogram and image plane
  // per camera, view RMS, map; each well formed, with its axes labelled.
  CHECK(plots == 0);
  CHECK_FALSE(fs::exists(dir + "/report/plots"));
  for (const auto& entry : fs::recursive_directory_iterator(dir + "/report")) {
    const std::string relative = fs::relative(entry.path(), dir + "/report").string();
    INFO(relative);
    CHECK((entry.is_directory() || relative == "index.html" ||
           relative.rfind("overlays/", 0) == 0 || relative.rfind("thumbs/", 0) == 0));
  }
  const auto svgs = SvgElements(html);
  REQUIRE(svgs.size() == 2 * 4 + 2);
  for (const auto& svg : svgs) {
    std::string why;
    const bool well_formed = WellFormed(svg, &why);
    INFO(why);
    CHECK(well_formed);
  }
  CHECK_THAT(svgs[0], Contains("Cell from above") && Contains(">x_base (m)</text>") &&
                          Contains(">y_base (m)</text>") && Contains("° down)</text>"));
  CHECK_THAT(svgs[1], Contains(">view RMS (px)</text>") && Contains(">pose (dataset order)</text>"));
  CHECK_THAT(svgs[2], Contains(">cam0: ") && Contains(">reprojection error (px)</text>") &&
                          Contains(">points</text>") && Contains(">RMS "));
  CHECK_THAT(svgs[6], Contains("cam0: residuals in the image (vectors ×") &&
                          Contains(">u (px)</text>") && Contains(">v (px)</text>"));

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
    for (const Warning& w : good.warnings) {
      INFO(w.text);
      CHECK(w.text.find("disagree") == std::string::npos);
      CHECK(w.text.find("large residuals") == std::string::npos);
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
  for (const Warning& w : bad.warnings) all += w.text + "\n";
  INFO(all);
  CHECK_THAT(all, Contains("camera 'cam2': large residuals"));
  CHECK_THAT(all, Contains("camera 'cam2': the result and Park's per-camera closed form disagree"));
  CHECK(all.find("camera 'cam1': the result") == std::string::npos);
  CHECK_THAT(test::ReadText(dir + "/bad/index.html"), Contains("disagree"));
}

TEST_CASE("report flags a camera's row by the warnings' camera, not by their wording", "[report]") {
  const std::string dir = test::TempDir("report_flagged_rows");
  Cell cell = MakeCell(Setup::kEyeToHand, 12, "");
  ReportOptions options;
  options.threads = 1;
  const auto flagged_rows = [&](const std::string& folder) {
    const std::string html = test::ReadText(folder + "/index.html");
    int rows = 0;
    for (size_t at = html.find("<tr class=\"flag\">"); at != std::string::npos;
         at = html.find("<tr class=\"flag\">", at + 1))
      ++rows;
    return rows;
  };
  cell.result.warnings.clear();
  WriteReport(cell.scene.dataset, cell.result, dir + "/none", options);
  const int unflagged = flagged_rows(dir + "/none");
  // A warning about one view of cam1 leaves its row alone; one about cam1 as
  // a whole flags it, whatever its sentence starts with.
  Warning view = CameraWarning(WarningKind::kViewLeftOut, "cam1", "camera 'cam1' view left out (test)");
  view.pose = cell.result.views[0].pose_id;
  view.view = 0;
  cell.result.warnings = {view};
  WriteReport(cell.scene.dataset, cell.result, dir + "/view", options);
  CHECK(flagged_rows(dir + "/view") == unflagged);
  cell.result.warnings = {CameraWarning(WarningKind::kLargeResiduals, "cam1", "large residuals (test)")};
  WriteReport(cell.scene.dataset, cell.result, dir + "/camera", options);
  CHECK(flagged_rows(dir + "/camera") == unflagged + 1);
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
  CHECK(WarningTexts(summary.warnings) == written);
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
    for (const Warning& w : Diagnose(dataset, options, &result))
      if (w.kind == WarningKind::kPoorRotationSpread && w.camera == "cam0") return true;
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
  const std::string html = test::ReadText(dir + "/index.html");
  CHECK_THAT(html, Contains("Cell from above") && Contains(">target (fixed)</text>") &&
                       Contains(">camera at a pose, view axis</text>"));
  CHECK_FALSE(fs::exists(dir + "/plots"));
  // No images: the overlays are drawn on a neutral canvas of the camera's size.
  const Observation& first = cell.scene.dataset.observations.front();
  const cv::Mat overlay =
      cv::imread(dir + "/overlays/" + first.camera + "/" + first.pose_id + ".png");
  CHECK(overlay.cols == cell.scene.dataset.cameras[0].width);
}

TEST_CASE("report plots escape camera names and leave out what is not finite", "[report]") {
  const std::string dir = test::TempDir("report_svg_text");
  const std::string name = "cam<&>\"1'";
  Cell cell = MakeCell(Setup::kEyeToHand, 8, "", name);
  REQUIRE(cell.result.cameras[1].name == name);
  REQUIRE(cell.result.cameras[1].calibrated);
  // NaN where a broken input or solve would put it: a detected point, a view's
  // RMS and a camera's RMS.
  Dataset& dataset = cell.scene.dataset;
  dataset.observations.front().points_px.front().x() = std::nan("");
  REQUIRE(!cell.result.views.empty());
  cell.result.views.front().rms_px = std::numeric_limits<double>::quiet_NaN();
  cell.result.cameras[0].rms_px = std::numeric_limits<double>::infinity();
  ReportOptions options;
  options.threads = 1;
  WriteReport(dataset, cell.result, dir, options);
  const std::string html = test::ReadText(dir + "/index.html");
  CHECK(html.find("<&>") == std::string::npos);
  const auto svgs = SvgElements(html);
  REQUIRE(svgs.size() == 2 * 4 + 2);
  const std::regex not_finite(R"(\b(nan|inf|infinity)\b)", std::regex::icase);
  for (const auto& svg : svgs) {
    std::string why;
    const bool well_formed = WellFormed(svg, &why);
    INFO(why);
    CHECK(well_formed);
    CHECK_FALSE(std::regex_search(svg, not_finite));
  }
  const std::string escaped = "cam&lt;&amp;&gt;&quot;1&#39;";
  CHECK_THAT(svgs[0], Contains(">" + escaped + " (z "));          // map label
  CHECK_THAT(svgs[1], Contains(">" + escaped + "</text>"));       // legend
  CHECK_THAT(svgs[3], Contains(">" + escaped + ": "));            // histogram title
  CHECK_THAT(svgs[2], Contains(">RMS n/a px</text>"));           // cam0's RMS is not finite
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
