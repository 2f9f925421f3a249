// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye export RESULT --to FORMAT -o FILE`: the calibrated cameras (and the
// target) as static transforms for ROS 2 launch, URDF, tf_static YAML or
// OpenCV YAML (io/export.h describes the frames and formats).
#include "handeye/io/export.h"

#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/core/setup_frames.h"
#include "handeye/io/result_json.h"
#include "output_paths.h"

namespace handeye::tools {
namespace {

struct ExportArgs {
  std::string result;
  std::string format;
  std::string output;
  ExportOptions frames;
  std::vector<std::string> camera_frames;  // `--camera-frame CAMERA=FRAME`, as given
};

// `--camera-frame CAMERA=FRAME` values into frames->camera_frames; every
// error names the flag and the value as given.
void ParseCameraFrames(const std::vector<std::string>& values, ExportOptions* frames) {
  std::map<std::string, std::string> camera_of_frame;
  for (const std::string& value : values) {
    const auto bad = [&](const std::string& why) {
      return InputError("", "", "--camera-frame '" + value + "': " + why);
    };
    const std::size_t eq = value.find('=');
    if (eq == std::string::npos) throw bad("expected CAMERA=FRAME, e.g. cam0=camera_color_optical_frame");
    const std::string camera = value.substr(0, eq), frame = value.substr(eq + 1);
    if (camera.empty()) throw bad("the camera name before '=' is empty");
    if (frame.empty()) throw bad("the frame name after '=' is empty");
    ExportOptions alone;
    alone.camera_frames[camera] = frame;
    std::string why;
    if (!alone.Check(&why)) throw bad(why);
    if (!frames->camera_frames.emplace(camera, frame).second)
      throw bad("camera '" + camera + "' is given a frame twice");
    if (!camera_of_frame.emplace(frame, camera).second)
      throw bad("frame '" + frame + "' is already given to camera '" + camera_of_frame[frame] + "'");
    for (const std::string* robot_frame : {&frames->base_frame, &frames->ee_frame, &frames->target_frame})
      if (frame == *robot_frame) throw bad("frame '" + frame + "' is the name of a robot or target frame");
  }
}

// Every camera named by --camera-frame must be one of the result's.
void CheckCameraFramesKnown(const ExportOptions& frames, const CalibrationResult& result, const std::string& file) {
  for (const auto& named : frames.camera_frames) {
    bool known = false;
    std::string names;
    for (const CameraResult& camera : result.cameras) {
      known = known || camera.name == named.first;
      names += (names.empty() ? "" : ", ") + camera.name;
    }
    if (!known)
      throw InputError("", "", "--camera-frame '" + named.first + "=" + named.second + "': " + file +
                                   " has no camera '" + named.first + "' (its cameras: " + names + ")");
  }
}

void RunExport(const ExportArgs& args) {
  const auto format = ParseExportFormat(args.format);
  if (!format) {
    std::string names;
    for (const auto& n : ExportFormatNames()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("", "", "--to: expected one of " + names + "; got '" + args.format + "'");
  }
  ExportOptions frames = args.frames;
  ParseCameraFrames(args.camera_frames, &frames);
  std::string why;
  if (!frames.Check(&why)) throw InputError("", "", "invalid frame option: " + why);
  const CalibrationResult result = LoadResult(args.result);
  CheckFileOutputs({{"RESULT", args.result}}, {{"-o", args.output}});
  CheckCameraFramesKnown(frames, result, args.result);
  std::vector<Warning> warnings;
  try {
    ExportResult(result, *format, frames, args.result, args.output, &warnings);
  } catch (const InputError& e) {
    throw e.file().empty() ? e.WithFile(args.result) : e;
  }
  PrintWarnings(warnings);
  int cameras = 0;
  for (const auto& camera : result.cameras) cameras += camera.calibrated ? 1 : 0;
  std::cerr << "wrote " << args.output << " (" << ExportFormatName(*format) << ": " << cameras
            << " cameras" << (frames.optical_only ? " as optical frames only" : "")
            << " and the target, parent frame "
            << frames.RosName(FramesOf(result.setup).mount) << ")\n";
}

}  // namespace

void RegisterExport(CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "export", "write the calibrated transforms for ROS 2 (launch, URDF, tf_static YAML) or OpenCV (YAML)");
  cmd->add_option("RESULT", args->result, "handeye-result/1 file")->required();
  cmd->add_option("--to", args->format, "ros2-launch, urdf, tf-static-yaml or opencv-yaml")->required();
  cmd->add_option("-o,--output", args->output, "file to write")->required();
  cmd->add_option("--base-frame", args->frames.base_frame, "robot base frame (default base_link)");
  cmd->add_option("--ee-frame", args->frames.ee_frame, "frame the robot reports, flange or TCP (default tool0)");
  cmd->add_option("--target-frame", args->frames.target_frame, "calibration target frame (default calibration_target)");
  cmd->add_option("--camera-frame", args->camera_frames,
                  "CAMERA=FRAME: name of the camera's optical frame, e.g. cam0=camera_color_optical_frame "
                  "(repeat per camera; default <camera>_optical_frame)")
      ->allow_extra_args(false);  // one value per --camera-frame, so RESULT after it stays positional
  cmd->add_flag("--optical-only", args->frames.optical_only,
                "one transform per camera, robot frame -> optical frame, and no <camera>_link (for camera "
                "drivers that publish their own body -> optical transform)");
  cmd->callback([args]() { RunExport(*args); });
}

HANDEYE_SUBCOMMAND(90, RegisterExport);

}  // namespace handeye::tools
