// SPDX-License-Identifier: GPL-2.0-or-later
// The report's "what to capture next" section: the poses `handeye advise`
// proposes for the result's own capture, for the camera that needs them.
#include <catch2/catch.hpp>
#include <memory>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/report/report.h"
#include "handeye/sim/synthetic.h"
#include "support/projected_scene.h"
#include "support/test_support.h"

using namespace handeye;
using Catch::Matchers::Contains;

namespace {

/// A small 4-camera cell whose cam0 kept only 4 views, calibrated (its
/// worst camera is cam3, not cam0).
struct FewViewsCell {
  SyntheticScene scene;
  CalibrationResult result;
};

FewViewsCell MakeFewViewsCell() {
  SceneOptions options;
  options.cell = "small";
  options.num_cameras = 4;
  options.num_poses = 16;
  options.seed = 8;
  options.width = 960;
  options.height = 540;
  FewViewsCell cell;
  cell.scene = test::ProjectedScene(options, 0.2, 4, 2);
  int kept = 0;
  std::vector<Observation> observations;
  for (const Observation& obs : cell.scene.dataset.observations)
    if (obs.camera != "cam0" || kept++ < 4) observations.push_back(obs);
  cell.scene.dataset.observations = observations;
  cell.result = Calibrate(cell.scene.dataset, CalibrationOptions{});
  return cell;
}

}  // namespace

TEST_CASE("report: what to capture next names the camera above the goal and poses that see it",
          "[report]") {
  const std::string dir = test::TempDir("report_next");
  const FewViewsCell cell = MakeFewViewsCell();
  ReportOptions options;
  options.threads = 1;
  options.next_poses = 3;
  options.next_goal_mm = 1e-3;  // far below any camera: every one named, all 3 proposed
  WriteReport(cell.scene.dataset, cell.result, dir + "/goal", options);
  const std::string html = test::ReadText(dir + "/goal/index.html");
  REQUIRE_THAT(html, Contains("<h2 id=\"next\">What to capture next</h2>"));
  const std::string section = html.substr(html.find("<h2 id=\"next\">"));
  CHECK_THAT(section, Contains("Predicted above the goal of 0.001 mm: <b>cam0</b> <b>cam1</b> "
                               "<b>cam2</b> <b>cam3</b>."));
  // σ now, per camera, and its part from the views alone: the camera worst
  // in that part is the one the first proposal is for.
  const std::regex now_row("<tr><td>(cam[0-9])</td><td>([0-9.]+)</td><td>([0-9.]+)</td>");
  std::string worst;
  double worst_mm = 0, worst_own_mm = 0;
  for (auto m = std::sregex_iterator(section.begin(), section.end(), now_row);
       m != std::sregex_iterator(); ++m) {
    CHECK(std::stod((*m)[3]) <= std::stod((*m)[2]));
    worst_mm = std::max(worst_mm, std::stod((*m)[2]));
    if (std::stod((*m)[3]) > worst_own_mm) worst_own_mm = std::stod((*m)[3]), worst = (*m)[1];
  }
  REQUIRE_FALSE(worst.empty());
  // The proposals: one row per pose (pose id, position, rpy, seen by, σ after per camera).
  const std::string proposals = section.substr(section.find("T_base_ee position, mm"));
  const std::string table = proposals.substr(0, proposals.find("</table>"));
  const std::regex pose_row(
      "<tr><td>[^<]+</td><td>[^<]+</td><td>[^<]+</td><td>([^<]*)</td>((<td>[0-9.]+</td>){4})</tr>");
  std::vector<std::smatch> rows;
  for (auto m = std::sregex_iterator(table.begin(), table.end(), pose_row);
       m != std::sregex_iterator(); ++m)
    rows.push_back(*m);
  REQUIRE(rows.size() == 3);
  CHECK_THAT(rows[0][1].str(), Contains(worst));
  // After the last proposal, every camera's σ is below the worst one now.
  const std::string last = rows.back()[2].str();
  const std::regex cell_value("<td>([0-9.]+)</td>");
  for (auto m = std::sregex_iterator(last.begin(), last.end(), cell_value);
       m != std::sregex_iterator(); ++m)
    CHECK(std::stod((*m)[1]) < worst_mm);

  options.next_goal_mm = 1e6;  // every camera within it: said in one line, nothing proposed
  WriteReport(cell.scene.dataset, cell.result, dir + "/reached", options);
  const std::string reached = test::ReadText(dir + "/reached/index.html");
  CHECK_THAT(reached, Contains("Every camera is predicted within the goal of 1000000.000 mm."));
  CHECK(reached.find("T_base_ee position, mm") == std::string::npos);

  options.next_poses = 0;  // the section left out
  WriteReport(cell.scene.dataset, cell.result, dir + "/none", options);
  CHECK(test::ReadText(dir + "/none/index.html").find("What to capture next") == std::string::npos);
  options.next_poses = 21;
  CHECK_THROWS_AS(WriteReport(cell.scene.dataset, cell.result, dir + "/bad", options),
                  std::invalid_argument);
}
