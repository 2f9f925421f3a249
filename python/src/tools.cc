// SPDX-License-Identifier: GPL-2.0-or-later
// handeye.detect, check, export and simulate: the library calls of the CLI's
// subcommands (tools/detect.cc, check.cc, export.cc, simulate.cc).
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <tuple>

#include "../../tools/output_paths.h"
#include "../../tools/target_options.h"
#include "bindings.h"
#include "convert.h"
#include "handeye/core/drift.h"
#include "handeye/core/error.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/detection.h"
#include "handeye/io/export.h"
#include "handeye/io/result_json.h"
#include "handeye/io/warning_json.h"
#include "handeye/sim/simulation.h"
#include "image.h"
#include "progress.h"
#include "result.h"

namespace handeye::python {
namespace {

py::object Detect(py::handle image, py::handle target) {
  const GrayImage gray(image, "image");
  const auto found = DetectIn(gray, TargetFrom(target));
  if (!found) return py::none();
  Eigen::MatrixXd px(found->points_px.size(), 2);
  for (std::size_t i = 0; i < found->points_px.size(); ++i)
    px.row(i) = found->points_px[i].transpose();
  return py::make_tuple(py::array_t<int>(found->ids.size(), found->ids.data()), MatrixArray(px));
}

// A Result, or the path of a result file.
CalibrationResult ResultFrom(py::handle result) {
  if (py::isinstance<py::str>(result)) return LoadResult(result.cast<std::string>());
  if (py::isinstance<PyResult>(result)) return result.cast<const PyResult&>().result;
  throw InputError("", "result",
                   "expected a handeye.Result or the path of a handeye-result/1 file");
}

// A Dataset, or a dataset / observations file, with its observations
// detected when it has only images (as `handeye check` does).
PyDataset DetectedDataset(py::handle source, int threads, py::object progress) {
  PyDataset data;
  if (py::isinstance<py::str>(source)) {
    data.path = source.cast<std::string>();
    data.dataset = WithoutGil([&] { return LoadDataset(data.path, {}, &data.warnings); });
    WarnAll(data.warnings);
  } else if (py::isinstance<PyDataset>(source)) {
    data = source.cast<const PyDataset&>();
  } else {
    throw InputError("", "source",
                     "expected a dataset or observations file path, or a handeye.Dataset");
  }
  if (data.dataset.observations.empty()) {
    Progress report(std::move(progress));
    DetectOptions detect;
    detect.threads = threads;
    detect.progress = report.Hook();
    WithoutGil([&] { DetectAll(&data.dataset, detect); });
    report.Rethrow();
  }
  return data;
}

py::dict DriftDict(const DriftResult& drift, const DriftOptions& options) {
  py::dict cameras;
  py::list moved, not_assessed;
  for (const CameraDrift& c : drift.cameras) {
    py::dict entry;
    entry["verdict"] = c.verdict;
    if (!c.reason.empty()) entry["reason"] = c.reason;
    entry["views"] = c.views;
    if (c.estimated) {
      entry["moved_mm"] = c.moved_mm;
      entry["moved_deg"] = c.moved_deg;
      entry["sigma_mm"] = c.sigma_mm;
      entry["sigma_deg"] = c.sigma_deg;
      entry["T_cam"] = TransformArray(c.T_cam);
    }
    if (c.verdict == "moved") moved.append(c.name);
    if (c.verdict == "not_assessed") not_assessed.append(c.name);
    cameras[py::str(c.name)] = entry;
  }
  py::dict out;
  out["format"] = "handeye-check/1";
  out["tolerance_mm"] = options.tolerance_mm;
  out["tolerance_deg"] = options.tolerance_deg;
  out["cameras"] = cameras;
  nlohmann::ordered_json warnings;
  AddWarningsJson(drift.warnings, &warnings);
  const py::object json_loads = py::module_::import("json").attr("loads");
  out["warnings"] = json_loads(warnings["warnings"].dump());
  out["warning_details"] = json_loads(warnings["warning_details"].dump());
  out["moved"] = moved;
  out["not_assessed"] = not_assessed;
  return out;
}

py::dict Check(py::handle result, py::handle source, double tolerance_mm, double tolerance_deg,
               int threads, py::object progress) {
  CheckThreads(threads);
  DriftOptions options;
  options.tolerance_mm = tolerance_mm;
  options.tolerance_deg = tolerance_deg;
  options.threads = threads > 0 ? threads : 1;
  const CalibrationResult calibration = ResultFrom(result);
  const PyDataset data = DetectedDataset(source, threads, std::move(progress));
  try {
    const DriftResult drift =
        WithoutGil([&] { return CheckDrift(data.dataset, calibration, options); });
    return DriftDict(drift, options);
  } catch (const InputError& e) {
    throw e.file().empty() && !data.path.empty() ? e.WithFile(data.path) : e;
  }
}

std::string Export(py::handle result, const std::string& to, py::object path,
                   const ExportOptions& given, py::object camera_frames) {
  const auto format = ParseExportFormat(to);
  if (!format) {
    std::string names;
    for (const auto& n : ExportFormatNames()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("", "to", "expected one of " + names + "; got '" + to + "'");
  }
  ExportOptions frames = given;
  if (!camera_frames.is_none())
    frames.camera_frames = camera_frames.cast<std::map<std::string, std::string>>();
  std::string why;
  if (!frames.Check(&why)) throw InputError("", "", "invalid frame option: " + why);
  const CalibrationResult calibration = ResultFrom(result);
  const std::string source =
      py::isinstance<py::str>(result) ? result.cast<std::string>() : "handeye.Result";
  std::vector<Warning> warnings;
  std::string text;
  try {
    text = FormatExport(calibration, *format, frames, source, &warnings);
    if (!path.is_none()) {
      tools::CheckFileOutputs({{"RESULT", py::isinstance<py::str>(result) ? source : ""}},
                              {{"path", path.cast<std::string>()}});
      ExportResult(calibration, *format, frames, source, path.cast<std::string>(), &warnings);
    }
  } catch (const InputError& e) {
    throw e.file().empty() && source != "handeye.Result" ? e.WithFile(source) : e;
  }
  WarnAll(warnings);
  return text;
}

struct SimulateCall {
  std::string outdir, cell, preset, setup, target_type;
  int cameras, poses, swap_poses, threads;
  std::uint64_t seed, pose_seed;
  double pose_noise_mm, pose_noise_deg, blur, noise;
  bool see_through, visible_only, distortion;
  py::object target, bump_camera, image_size, progress;
};

SceneOptions SceneOf(const SimulateCall& call) {
  SceneOptions options;
  if (!call.preset.empty() && !call.cell.empty())
    throw InputError("", "preset", "expected either cell or preset, not both");
  if (!call.preset.empty() && call.preset != "metric-medium")
    throw InputError("", "preset", "expected metric-medium, got '" + call.preset + "'");
  options.cell = !call.preset.empty() ? call.preset : !call.cell.empty() ? call.cell : "medium";
  const auto setup = ParseSetup(call.setup);
  if (!setup)
    throw InputError("", "setup", "expected eye_to_hand or eye_in_hand, got '" + call.setup + "'");
  options.setup = *setup;
  options.num_cameras = call.cameras;
  options.num_poses = call.poses;
  options.seed = call.seed;
  options.distortion = call.distortion;
  options.pose_noise_mm = call.pose_noise_mm;
  options.pose_noise_deg = call.pose_noise_deg;
  options.swap_poses = call.swap_poses;
  options.pose_seed = call.pose_seed;
  if (!call.bump_camera.is_none()) {
    const auto bump = call.bump_camera.cast<std::tuple<std::string, double, double>>();
    std::tie(options.bumped_camera, options.bump_mm, options.bump_deg) = bump;
  }
  if (!call.image_size.is_none()) {
    const std::vector<double> size = FiniteVector(call.image_size, "image_size");
    if (size.size() != 2 || size[0] != std::floor(size[0]) || size[1] != std::floor(size[1]) ||
        size[0] < 1 || size[1] < 1 || size[0] > 1e5 || size[1] > 1e5)
      throw InputError("", "image_size", "expected (width, height) in whole pixels");
    options.width = static_cast<int>(size[0]);
    options.height = static_cast<int>(size[1]);
  }
  std::string why;
  if (!options.Check(&why)) throw InputError("", "", "bad scene options: expected " + why);
  return options;
}

py::dict Simulate(const SimulateCall& call) {
  const SceneOptions scene_options = SceneOf(call);
  std::vector<Warning> warnings;
  std::shared_ptr<const Target> target;
  if (call.target
          .is_none())  // the CLI's default sheet (METRIC's board for the metric-medium preset)
    target =
        tools::MakeTargetFromOptions(tools::TargetOptions{}, scene_options.cell == "metric-medium");
  else
    target = TargetFrom(call.target, &warnings);
  WarnAll(warnings);
  RenderOptions render;
  render.blur_sigma_px = call.blur;
  render.noise_sigma = call.noise;
  render.seed = call.seed;
  render.see_through = call.see_through;
  render.every_view = !call.visible_only;
  std::string why;
  if (!render.Check(&why)) throw InputError("", "blur/noise", "expected " + why);
  CheckThreads(call.threads);
  std::error_code ec;
  std::filesystem::create_directories(call.outdir, ec);
  if (!std::filesystem::is_directory(call.outdir, ec))
    throw InputError(call.outdir, "", "cannot create the output folder");
  SyntheticScene scene = MakeScene(scene_options, target);
  Progress report(call.progress);
  const auto hook = report.Hook();
  WithoutGil([&] { WriteSimulation(&scene, render, call.outdir, call.threads, hook); });
  report.Rethrow();
  py::dict out;
  const std::filesystem::path dir(call.outdir);
  out["dataset"] = (dir / "dataset.json").string();
  out["ground_truth"] = (dir / "ground_truth.json").string();
  std::size_t images = 0;
  for (const auto& pose : scene.dataset.poses) images += pose.images.size();
  out["images"] = images;
  py::list swapped;
  for (const auto& [a, b] : scene.swapped_poses) swapped.append(py::make_tuple(a, b));
  out["swapped_poses"] = swapped;
  return out;
}

}  // namespace

void AddTools(py::module_& m) {
  m.def("detect", &Detect, py::arg("image"), py::arg("target") = "checkerboard",
        "Runs the target's detector on one image array (H×W uint8/uint16, or H×W×3 BGR): (ids, "
        "pixels N×2), or "
        "None when the target is not found.");
  m.def(
      "check", &Check, py::arg("result"), py::arg("source"), py::kw_only(),
      py::arg("tolerance_mm") = 1.0, py::arg("tolerance_deg") = 0.1, py::arg("threads") = 0,
      py::arg("progress") = py::none(),
      "Has a camera moved since `result`? As `handeye check`: the handeye-check/1 content as a "
      "dict, plus each assessed camera's new T_cam and the lists `moved` (non-empty where the CLI "
      "exits 4) and `not_assessed` (else non-empty where it exits 3).");
  m.def(
      "export",
      [](py::handle result, const std::string& to, py::object path, const std::string& base_frame,
         const std::string& ee_frame, const std::string& target_frame, py::object camera_frames,
         bool optical_only) {
        ExportOptions frames;
        frames.base_frame = base_frame;
        frames.ee_frame = ee_frame;
        frames.target_frame = target_frame;
        frames.optical_only = optical_only;
        return Export(result, to, path, frames, camera_frames);
      },
      py::arg("result"), py::arg("to"), py::arg("path") = py::none(), py::kw_only(),
      py::arg("base_frame") = "base_link", py::arg("ee_frame") = "tool0",
      py::arg("target_frame") = "calibration_target", py::arg("camera_frames") = py::none(),
      py::arg("optical_only") = false,
      "The result as ros2-launch, urdf, tf-static-yaml or opencv-yaml text (as `handeye export`); "
      "also "
      "written to `path` when given.");
  m.def(
      "simulate",
      [](const std::string& outdir, const std::string& cell, const std::string& preset, int cameras,
         int poses, py::object target, const std::string& setup, std::uint64_t seed,
         double pose_noise_mm, double pose_noise_deg, int swap_poses, std::uint64_t pose_seed,
         py::object bump_camera, bool see_through, bool visible_only, bool distortion, double blur,
         double noise, int threads, py::object image_size, py::object progress) {
        return Simulate(SimulateCall{
            outdir,         cell,        preset,     setup,       "",           cameras,
            poses,          swap_poses,  threads,    seed,        pose_seed,    pose_noise_mm,
            pose_noise_deg, blur,        noise,      see_through, visible_only, distortion,
            target,         bump_camera, image_size, progress});
      },
      py::arg("outdir"), py::kw_only(), py::arg("cell") = "", py::arg("preset") = "",
      py::arg("cameras") = 4, py::arg("poses") = 20, py::arg("target") = py::none(),
      py::arg("setup") = "eye_to_hand", py::arg("seed") = 1, py::arg("pose_noise_mm") = 0.0,
      py::arg("pose_noise_deg") = 0.0, py::arg("swap_poses") = 0, py::arg("pose_seed") = 0,
      py::arg("bump_camera") = py::none(), py::arg("see_through") = false,
      py::arg("visible_only") = false, py::arg("distortion") = true, py::arg("blur") = 0.75,
      py::arg("noise") = 2.0, py::arg("threads") = 0, py::arg("image_size") = py::none(),
      py::arg("progress") = py::none(),
      "Renders a synthetic workcell into outdir (dataset.json, ground_truth.json, images/), as "
      "`handeye "
      "simulate`; returns the paths and counts. bump_camera: (name, mm, deg).");
}

}  // namespace handeye::python
