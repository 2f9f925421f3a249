// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye calibrate DATASET|OBS -o RESULT.json [--method M] [--report DIR]`:
// detects if the input has only images, initialises, solves and writes
// handeye-result/1 (and the report, with --report).
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

#include "cli_numbers.h"
#include "commands.h"
#include "handeye/core/calibration.h"
#include "handeye/core/error.h"
#include "handeye/core/setup_frames.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/detection.h"
#include "handeye/io/repeated_images.h"
#include "handeye/io/result_json.h"
#include "handeye/report/report.h"
#include "report_folder.h"

namespace handeye::tools {
namespace {

struct CalibrateArgs {
  bool quiet = false;  // --quiet: no progress line
  std::string input;
  std::string output;
  std::string method = "joint";
  double cauchy_scale_px = 0.0;  // 0: from the data
  bool no_cross_terms = false;
  bool keep_all_views = false;
  double robot_sigma_mm = -1;  // < 0: estimated
  double robot_sigma_deg = -1;
  int threads = 0;
  bool reorthonormalise = false;
  std::string report;  // --report DIR
  std::string refine_intrinsics;  // --refine-intrinsics LIST
  std::string intrinsics_sigma;   // --intrinsics-sigma focal=P%,principal_point=Npx | 0
  std::string from;               // --from RESULT
  std::string keep_cameras;       // --keep-cameras LIST
  bool cross_validate = false;
  bool no_closed_form = false;
  bool accept_setup = false;  // --accept-setup: no setup-mistake checks
  std::string observations_out;  // --observations-out FILE
};

// The robot's σ is one model, position and rotation together: say so in the
// flags' terms before the library's own check.
void CheckRobotSigmas(const CalibrateArgs& args) {
  const bool mm = args.robot_sigma_mm >= 0, deg = args.robot_sigma_deg >= 0;
  if (mm != deg)
    throw InputError(
        "", "",
        std::string(mm ? "--robot-sigma-mm" : "--robot-sigma-deg") +
            " given alone: give --robot-sigma-mm and --robot-sigma-deg together (both 0: the "
            "robot's poses are exact; neither: its error is estimated from the views)");
  if (mm && (args.robot_sigma_mm == 0) != (args.robot_sigma_deg == 0))
    throw InputError(
        "", "",
        "--robot-sigma-mm and --robot-sigma-deg: 0 means an exact robot, in position and rotation "
        "together: give both 0, or both > 0");
}

void PrintSummary(const CalibrationResult& result) {
  const std::string mount = FramesOf(result.setup).mount;
  std::printf("method %s, %s\n", MethodName(result.method), SetupName(result.setup));
  std::printf("%-12s %10s %10s %10s %8s %6s\n", "camera", ("x_" + mount + " mm").c_str(),
              ("y_" + mount + " mm").c_str(), ("z_" + mount + " mm").c_str(), "rms px", "views");
  for (const CameraResult& cam : result.cameras) {
    if (!cam.calibrated) {
      std::printf("%-12s %10s %10s %10s %8s %6d\n", cam.name.c_str(), "-", "-", "-", "-", cam.views);
      continue;
    }
    const Eigen::Vector3d t = 1000.0 * cam.T_cam.translation();
    std::printf("%-12s %10.2f %10.2f %10.2f %8.3f %6d\n", cam.name.c_str(), t.x(), t.y(), t.z(), cam.rms_px,
                cam.views);
  }
  std::printf("rms %.3f px, AX=ZB %.3f mm (cameras in the %s frame; %.3f mm in the target frame) / %.4f deg, "
              "%d iterations, %.3f s\n",
              result.metrics.rms_px, result.metrics.axzb_camera_translation_mm, mount.c_str(),
              result.metrics.axzb_translation_mm, result.metrics.axzb_rotation_deg, result.solver.iterations,
              result.solver.seconds);
  for (const CameraResult& cam : result.cameras)
    if (cam.cross_validation)
      std::printf("%-12s held out: RMS %.3f px over %d poses; pose spread over the folds %.3f mm / %.4f deg\n",
                  cam.name.c_str(), cam.cross_validation->held_out_rms_px, cam.cross_validation->folds,
                  cam.cross_validation->position_spread_mm, cam.cross_validation->rotation_spread_deg);
  int left_out = 0;
  for (const ViewResult& view : result.views) left_out += view.used ? 0 : 1;
  if (result.solver.cauchy_scale_px > 0)
    std::printf("Cauchy loss scale %.3g px, %d solve%s, %d of %zu views left out%s\n",
                result.solver.cauchy_scale_px, result.solver.rounds, result.solver.rounds == 1 ? "" : "s",
                left_out, result.views.size(), result.solver.converged ? "" : ", NOT CONVERGED");
}

void RunCalibrate(const CalibrateArgs& args) {
  CalibrationOptions options;
  const auto method = ParseMethod(args.method);
  if (!method) {
    std::string names;
    for (const auto& n : MethodNames()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("", "", "--method: expected one of " + names + "; got '" + args.method + "'");
  }
  options.method = *method;
  options.cauchy_scale_px = args.cauchy_scale_px;
  options.cross_terms = !args.no_cross_terms;
  options.compare_closed_form = !args.no_closed_form;
  options.reject_views = !args.keep_all_views;
  CheckRobotSigmas(args);
  options.check_setup = !args.accept_setup;
  options.robot_sigma_mm = args.robot_sigma_mm;
  options.robot_sigma_deg = args.robot_sigma_deg;
  if (!args.refine_intrinsics.empty()) {
    std::string list_why;
    const auto groups = ParseIntrinsicsGroups(args.refine_intrinsics, &list_why);
    if (!groups) throw InputError("", "", "--refine-intrinsics: " + list_why);
    options.refine_intrinsics = *groups;
  }
  if (!args.intrinsics_sigma.empty()) {
    std::string sigma_why;
    const auto sigma = ParseIntrinsicsSigma(args.intrinsics_sigma, &sigma_why);
    if (!sigma) throw InputError("", "", "--intrinsics-sigma: " + sigma_why);
    options.intrinsics_sigma = *sigma;
  }
  std::optional<Setup> from_setup;
  if (!args.keep_cameras.empty() || !args.from.empty()) {
    if (args.keep_cameras.empty() || args.from.empty())
      throw InputError("", "", "--keep-cameras and --from go together: the cameras to hold, and the result "
                               "whose poses they keep");
    const CalibrationResult previous = LoadResult(args.from);
    from_setup = previous.setup;
    std::stringstream list(args.keep_cameras);
    std::string name;
    while (std::getline(list, name, ',')) {
      const auto it = std::find_if(previous.cameras.begin(), previous.cameras.end(),
                                   [&](const CameraResult& c) { return c.name == name; });
      if (it == previous.cameras.end() || !it->calibrated)
        throw InputError(args.from, "/cameras",
                         "--keep-cameras: a calibrated camera named '" + name + "' in the --from result");
      options.fixed_cameras[name] = it->T_cam;
    }
  }
  options.cross_validate = args.cross_validate;
  options.threads = args.threads > 0 ? args.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::string why;
  if (!options.Check(&why)) throw InputError("", "", "invalid option: " + why);

  LoadOptions load;
  load.reorthonormalise = args.reorthonormalise;
  std::vector<Warning> warnings;
  Dataset dataset = LoadDataset(args.input, load, &warnings);
  PrintWarnings(warnings);
  // Before minutes of detection and solving: every output can be written and is no input.
  std::vector<NamedPath> inputs = ImageInputs(dataset);
  inputs.insert(inputs.end(), {{"INPUT", args.input}, {"--from", args.from}});
  const std::vector<NamedPath> outputs = {{"-o", args.output},
                                          {"--observations-out", args.observations_out}};
  CheckFileOutputs(inputs, outputs);
  CheckReportFolder(inputs, outputs, {"--report", args.report});
  if (from_setup && *from_setup != dataset.setup)
    throw InputError(args.from, "/setup",
                     std::string("the dataset's setup, ") + SetupName(dataset.setup) + ", for --from");
  std::vector<Warning> detect_warnings;
  if (dataset.observations.empty()) {
    bool has_images = false;
    for (const auto& pose : dataset.poses) has_images = has_images || !pose.images.empty();
    if (!has_images)
      throw InputError(args.input, "/observations", "observations, or poses with images to detect in");
    DetectOptions detect;
    detect.threads = args.threads;
    detect.progress = ProgressLine("detecting", args.quiet);
    PrintWarnings(RepeatedImageWarnings(dataset));
    detect_warnings = DetectAll(&dataset, detect);
    PrintWarnings(detect_warnings);
  }
  if (!args.observations_out.empty()) {
    // Before the solve, so that a calibration that fails (or is rerun with
    // other options) need not detect again.
    SaveObservations(dataset, args.observations_out);
    std::fprintf(stderr, "wrote %s (%zu views)\n", args.observations_out.c_str(), dataset.observations.size());
  }
  CalibrationResult result;
  try {
    result = Calibrate(dataset, options);
  } catch (const InputError& e) {
    throw e.file().empty() ? e.WithFile(args.input) : e;
  } catch (const SolveError& e) {
    // A target declared differently from the one in the images is the likely
    // reason for too few views: say so where the failure is reported.
    std::string why = e.what();
    for (const Warning& warning : detect_warnings) why += "; " + warning.text;
    throw SolveError(why);
  }
  result.input = args.input;
  PrintWarnings(result.warnings);
  for (const auto& note : result.notes) std::cerr << "note: " << note << "\n";
  SaveResult(result, args.output);
  PrintSummary(result);
  std::fprintf(stderr, "wrote %s\n", args.output.c_str());
  if (!args.report.empty()) {
    // The same report as `handeye report DATASET RESULT -o DIR`, from the data in memory.
    ReportOptions report;
    report.threads = args.threads;
    report.dataset_label = args.input;
    report.result_label = args.output;
    report.progress = ProgressLine("drawing overlays", args.quiet);
    const ReportSummary written = WriteReportFolder(dataset, result, args.report, report);
    std::fprintf(stderr, "wrote %s (%zu warnings: see the report)\n", written.index_html.c_str(),
                 written.warnings.size());
  }
}

}  // namespace

void RegisterCalibrate(CLI::App& app) {
  auto args = std::make_shared<CalibrateArgs>();
  CLI::App* cmd = app.add_subcommand("calibrate", "calibrate every camera against the robot");
  cmd->add_option("INPUT", args->input, "handeye-dataset/1 (detects first) or handeye-observations/1")
      ->required();
  cmd->add_option("-o,--output", args->output, "result file to write (handeye-result/1)")->required();
  cmd->add_option("--method", args->method,
                  "joint (default, the paper's method), per-camera, tsai, park, horaud, andreff, "
                  "daniilidis, shah, li, visp");
  cmd->add_option("--cauchy-scale", args->cauchy_scale_px,
                  "Cauchy loss scale in pixels (default: 3 sigma of the residuals, at least 1)")
      ->check(NonNegativeNumber("0 (from the residuals) or a positive scale in pixels"));
  cmd->add_option("--robot-sigma-mm", args->robot_sigma_mm,
                  "joint: the robot's pose error, sigma per axis of the flange position in mm (with "
                  "--robot-sigma-deg; 0 and 0: poses exact; default: estimated from the views)")
      ->check(NonNegativeNumber("a non-negative sigma in mm"));
  cmd->add_option("--robot-sigma-deg", args->robot_sigma_deg,
                  "joint: the robot's rotation error, sigma per axis in degrees")
      ->check(NonNegativeNumber("a non-negative sigma in degrees"));
  cmd->add_flag("--keep-all-views", args->keep_all_views,
                "use every view with a plane pose, even those that disagree with the others");
  cmd->add_option("--refine-intrinsics", args->refine_intrinsics,
                  "joint: make these intrinsics of every camera unknowns of the solve: focal, "
                  "principal_point, distortion (comma-separated) or all");
  cmd->add_option("--intrinsics-sigma", args->intrinsics_sigma,
                  "how far off the given intrinsics may be (1 sigma), carried into every camera's sigma: "
                  "focal=P% (of fx and fy, one error for both) and/or principal_point=Npx (per axis), "
                  "comma-separated, or 0 (exact); default focal=1%,principal_point=3px");
  cmd->add_option("--from", args->from,
                  "an earlier result (handeye-result/1) whose camera poses --keep-cameras holds");
  cmd->add_option("--keep-cameras", args->keep_cameras,
                  "joint: hold these cameras (comma-separated) at their --from poses and solve only the "
                  "others, e.g. after `handeye check` found them moved");
  cmd->add_flag("--cross-validate", args->cross_validate,
                "joint: leave each robot pose out in turn, solve again and predict its views: held-out RMS "
                "and the spread of each camera's pose over the folds (one solve per pose)");
  cmd->add_flag("--accept-setup", args->accept_setup,
                "take the data as they are: no check for the usual setup mistakes (poses inverted, "
                "transposed, in another unit or order, the target's size off, images repeated) and no "
                "limit on the robot error estimated");
  cmd->add_flag("--no-cross-terms", args->no_cross_terms, "joint: leave out the camera-to-camera terms");
  cmd->add_flag("--no-closed-form", args->no_closed_form,
                "skip the comparison of each camera with a per-camera closed-form solution");
  cmd->add_option("--threads", args->threads, "threads for detection and the solver (0 = all cores)")
      ->check(ThreadCount());
  cmd->add_flag("--reorthonormalise", args->reorthonormalise,
                "replace slightly non-orthonormal robot rotations by the nearest rotation");
  cmd->add_option("--report", args->report,
                  "also write the HTML report and overlays into this folder");
  cmd->add_option("--observations-out", args->observations_out,
                  "also write the observations calibrated from (handeye-observations/1, as `detect -o` "
                  "writes: detected from the images, or as read), for `calibrate` or `report` without "
                  "detecting again");
  AddQuietFlag(cmd, &args->quiet);
  cmd->callback([args]() { RunCalibrate(*args); });
}

HANDEYE_SUBCOMMAND(20, RegisterCalibrate);

}  // namespace handeye::tools
