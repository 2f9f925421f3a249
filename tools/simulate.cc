// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye simulate OUTDIR`: renders a synthetic workcell (SPEC §7) into
// OUTDIR/dataset.json, OUTDIR/ground_truth.json and OUTDIR/images/.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli_numbers.h"
#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/io/plan_json.h"
#include "handeye/sim/plan_cell.h"
#include "handeye/sim/simulation.h"
#include "handeye/sim/synthetic.h"
#include "output_paths.h"
#include "target_options.h"

namespace handeye::tools {
namespace {

struct SimulateArgs {
  bool quiet = false;  // --quiet: no progress line
  std::string outdir;
  std::string cell;
  std::string preset;
  int cameras = 4;
  int poses = 20;
  TargetOptions target;
  std::string setup = "eye_to_hand";
  std::uint64_t seed = 1;
  double pose_noise_mm = 0;
  double pose_noise_deg = 0;
  int swap_poses = 0;
  std::uint64_t pose_seed = 0;
  std::string bump_camera;  // NAME:MM:DEG
  std::vector<std::string> poor_cameras;  // NAME:BLUR:NOISE
  bool see_through = false;
  bool visible_only = false;
  bool no_distortion = false;
  double blur_px = 0.75;
  double noise = 2.0;
  int threads = 0;
  std::string image_size;
  std::string poses_file;  // --poses-file: render these T_base_ee
  std::string cell_file;   // --write-cell: the cell as a planner sees it
};

InputError BadOption(const std::string& option, const std::string& expected) {
  return InputError("", option, expected);
}

/// A camera of the scene and two finite numbers, NAME:A:B.
struct CameraAndTwo {
  std::string camera;
  double first = 0, second = 0;
};

CameraAndTwo ParseCameraAndTwo(const std::string& option, const std::string& text,
                               const std::string& form, int cameras) {
  const std::string expected = form + ", got '" + text + "'";
  const auto first = text.find(':');
  const auto second = first == std::string::npos ? first : text.find(':', first + 1);
  if (second == std::string::npos) throw BadOption(option, "expected " + expected);
  CameraAndTwo out;
  out.camera = text.substr(0, first);
  try {
    size_t used = 0;
    const std::string a = text.substr(first + 1, second - first - 1);
    const std::string b = text.substr(second + 1);
    out.first = std::stod(a, &used);
    if (used != a.size()) throw std::invalid_argument(a);
    out.second = std::stod(b, &used);
    if (used != b.size()) throw std::invalid_argument(b);
  } catch (const std::exception&) {
    throw BadOption(option, "expected " + expected);
  }
  bool known = false;
  for (int k = 0; k < cameras; ++k) known = known || out.camera == "cam" + std::to_string(k);
  if (!known || !std::isfinite(out.first) || !std::isfinite(out.second))
    throw BadOption(option, "expected a camera cam0 … cam" + std::to_string(cameras - 1) +
                                " and finite numbers: " + expected);
  return out;
}

SceneOptions MakeSceneOptions(const SimulateArgs& args) {
  SceneOptions options;
  if (!args.preset.empty() && !args.cell.empty())
    throw BadOption("--preset", "expected either --cell or --preset, not both");
  if (!args.preset.empty() && args.preset != "metric-medium")
    throw BadOption("--preset", "expected metric-medium, got '" + args.preset + "'");
  options.cell = !args.preset.empty() ? args.preset : !args.cell.empty() ? args.cell : "medium";
  if (options.cell == "metric-medium" && args.preset.empty())
    throw BadOption("--cell", "expected small, medium or large (metric-medium is a --preset)");
  const auto setup = ParseSetup(args.setup);
  if (!setup) throw BadOption("--setup", "expected eye_to_hand or eye_in_hand, got '" + args.setup + "'");
  options.setup = *setup;
  options.num_cameras = args.cameras;
  options.num_poses = args.poses;
  options.seed = args.seed;
  options.distortion = !args.no_distortion;
  options.pose_noise_mm = args.pose_noise_mm;
  options.pose_noise_deg = args.pose_noise_deg;
  options.swap_poses = args.swap_poses;
  options.pose_seed = args.pose_seed;
  if (!args.bump_camera.empty()) {
    const CameraAndTwo bump = ParseCameraAndTwo("--bump-camera", args.bump_camera,
                                                "NAME:MM:DEG (e.g. cam1:5:0.2)", args.cameras);
    options.bumped_camera = bump.camera;
    options.bump_mm = bump.first;
    options.bump_deg = bump.second;
  }
  if (!args.image_size.empty()) {
    const auto [w, h] = ParseTwoCounts("--image-size", args.image_size, "WIDTHxHEIGHT in pixels");
    options.width = w;
    options.height = h;
  }
  if (!args.poses_file.empty()) {
    for (const PoseRow& row : ReadPoseFile(args.poses_file)) options.given_poses.push_back(row.T_base_ee);
    options.num_poses = static_cast<int>(options.given_poses.size());
  }
  std::string why;
  if (!options.Check(&why)) throw BadOption("", "bad scene options: expected " + why);
  return options;
}

void RunSimulate(const SimulateArgs& args) {
  const SceneOptions scene_options = MakeSceneOptions(args);
  const auto target = MakeTargetFromOptions(args.target, scene_options.cell == "metric-medium");
  PrintWarnings(target->Warnings());

  RenderOptions render;
  render.blur_sigma_px = args.blur_px;
  render.noise_sigma = args.noise;
  render.seed = args.seed;
  render.see_through = args.see_through;
  render.every_view = !args.visible_only;
  for (const std::string& text : args.poor_cameras) {
    const CameraAndTwo poor =
        ParseCameraAndTwo("--poor-camera", text, "NAME:BLUR:NOISE (e.g. cam1:3:8)", args.cameras);
    if (poor.first < 0 || poor.second < 0)
      throw BadOption("--poor-camera",
                      "expected a blur and a noise of 0 or more, got '" + text + "'");
    render.camera_quality[poor.camera] = {poor.first, poor.second};
  }
  std::string why;
  if (!render.Check(&why)) throw BadOption("--blur/--noise", "expected " + why);
  if (args.threads < 0) throw BadOption("--threads", "expected 0 (all cores) or more");

  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(args.outdir, ec);
  if (!fs::is_directory(args.outdir, ec))
    throw InputError(args.outdir, "", "cannot create the output folder");
  CheckFileOutputs(
      {{"--target-json", args.target.target_json}, {"--poses-file", args.poses_file}},
      {{"dataset.json in OUTDIR", (fs::path(args.outdir) / "dataset.json").string()},
       {"ground_truth.json in OUTDIR", (fs::path(args.outdir) / "ground_truth.json").string()},
       {"--write-cell", args.cell_file}});

  SyntheticScene scene = MakeScene(scene_options, target);
  WriteSimulation(&scene, render, args.outdir, args.threads, ProgressLine("rendering", args.quiet));
  // What a user would know before capturing: the poses by tape (± 20 mm, 1°).
  if (!args.cell_file.empty()) SavePlanCell(PlanCellOfScene(scene, RoughKnowledge{}), args.cell_file);

  std::size_t images = 0;
  for (const auto& pose : scene.dataset.poses) images += pose.images.size();
  std::map<std::string, int> views_per_camera;
  int views = 0, shared = 0;
  for (const auto& pose : scene.truth.poses) {
    for (const auto& [camera, obs] : pose.points_px) ++views_per_camera[camera];
    views += static_cast<int>(pose.points_px.size());
    shared += pose.points_px.size() >= 2 ? 1 : 0;
  }
  std::ostringstream per_camera;
  for (const auto& camera : scene.dataset.cameras)
    per_camera << (per_camera.tellp() > 0 ? ", " : "") << camera.name << " "
               << views_per_camera[camera.name];
  std::cout << "simulated " << SetupName(scene_options.setup) << " " << scene_options.cell
            << " cell: " << scene.dataset.cameras.size() << " cameras, " << scene.dataset.poses.size()
            << " poses, " << images << " images rendered, " << views
            << " show the whole target from the front (" << per_camera.str() << "), " << shared
            << " poses seen by 2+ cameras -> " << args.outdir << "\n";
  for (const auto& [a, b] : scene.swapped_poses)
    std::cout << "robot records of poses " << a << " and " << b << " exchanged (--swap-poses)\n";
}

}  // namespace

void RegisterSimulate(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "simulate", "render a synthetic workcell dataset with ground_truth.json");
  cmd->add_option("OUTDIR", args->outdir, "folder to write dataset.json, ground_truth.json and images/")
      ->required();
  cmd->add_option("--cell", args->cell, "cell size: small (~1.5 m), medium (~2.5 m), large (~4 m); default medium");
  cmd->add_option("--preset", args->preset,
                  "metric-medium: METRIC's synthetic medium cell (4 cameras, fx 1371.02, 4x3 board of 50 mm)");
  cmd->add_option("--cameras", args->cameras, "number of cameras (1..64)")
      ->check(IntegerIn(1, 64, "between 1 and 64 cameras"));
  auto* poses = cmd->add_option("--poses", args->poses, "number of robot poses")
                    ->check(IntegerIn(1, 100000, "between 1 and 100000 poses"));
  cmd->add_option("--poses-file", args->poses_file,
                  "render exactly these true T_base_ee instead of sampling poses: a handeye-plan/1 (or any JSON "
                  "with poses [{id, T_base_ee}]) or a CSV / YAML pose list as import-poses reads it, in metres")
      ->excludes(poses);
  cmd->add_option("--write-cell", args->cell_file,
                  "also write the cell as handeye plan reads it (handeye-cell/1): camera and target poses off by "
                  "a tape measure's error (20 mm, 1 deg), the simulator's reachable box");
  cmd->add_option("--target", args->target.type,
                  "target type: checkerboard (default), charuco or aprilgrid; each has a default sheet "
                  "(metric-medium: METRIC's 4x3 checkerboard of 50 mm)");
  AddTargetOptions(cmd, &args->target);
  cmd->add_option("--setup", args->setup, "eye_to_hand (default) or eye_in_hand");
  cmd->add_option("--seed", args->seed, "random seed; the same seed gives the same dataset")
      ->check(UnsignedInteger("a whole number from 0 to 2^64 - 1"));
  cmd->add_option("--pose-noise-mm", args->pose_noise_mm, "robot translation noise sigma per axis (mm) on the reported poses")
      ->check(NonNegativeNumber("a non-negative robot translation noise sigma in mm"));
  cmd->add_option("--pose-noise-deg", args->pose_noise_deg, "robot rotation noise sigma (deg) on the reported poses")
      ->check(NonNegativeNumber("a non-negative robot rotation noise sigma in degrees"));
  cmd->add_option("--swap-poses", args->swap_poses,
                  "exchange the robot records of K pairs of poses (a logging fault to test against)")
      ->check(NonNegativeNumber("a non-negative number of pose pairs"));
  cmd->add_option("--pose-seed", args->pose_seed,
                  "draw the robot poses from this seed, the cameras and target from --seed: a later "
                  "capture of the same cell")
      ->check(UnsignedInteger("a whole number from 0 to 2^64 - 1"));
  cmd->add_option("--bump-camera", args->bump_camera,
                  "NAME:MM:DEG: that camera was knocked since calibration: moved MM along its x axis, "
                  "turned DEG about its y axis (ground_truth.json has the bumped pose)");
  cmd->add_option(
      "--poor-camera", args->poor_cameras,
      "NAME:BLUR:NOISE: that camera's optics and sensor are poorer than the cell's (a cheaper or "
      "more distant camera, a lens out of focus): blur sigma BLUR px and sensor noise NOISE grey "
      "levels instead of its share of --blur and --noise; repeat for more cameras");
  cmd->add_flag("--see-through", args->see_through,
                "a glass target: cameras behind it see its pattern mirrored (a printed one shows a plain back)");
  cmd->add_flag("--visible-only", args->visible_only,
                "render only the views that show the whole target from the front (default: every camera at every pose)");
  cmd->add_flag("--no-distortion", args->no_distortion, "cameras without lens distortion");
  cmd->add_option("--blur", args->blur_px, "mean optical blur sigma (px); each camera gets 2/3..4/3 of it (default 0.75)")
      ->check(NonNegativeNumber("a non-negative blur sigma in pixels"));
  cmd->add_option("--noise", args->noise, "sensor noise sigma in grey levels (default 2)")
      ->check(NonNegativeNumber("a non-negative noise sigma in grey levels"));
  cmd->add_option("--threads", args->threads, "rendering threads (0 = all cores)")->check(ThreadCount());
  cmd->add_option("--image-size", args->image_size, "image size WIDTHxHEIGHT (default 1920x1080)");
  AddQuietFlag(cmd, &args->quiet);
  cmd->callback([args]() { RunSimulate(*args); });
}

HANDEYE_SUBCOMMAND(50, RegisterSimulate);

}  // namespace handeye::tools
