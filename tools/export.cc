// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye export RESULT --to FORMAT -o FILE`: the calibrated cameras (and the
// target) as static transforms for ROS 2 launch, URDF, tf_static YAML or
// OpenCV YAML (io/export.h describes the frames and formats).
#include <iostream>
#include <memory>

#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/io/export.h"
#include "handeye/io/result_json.h"

namespace handeye::tools {
namespace {

struct ExportArgs {
  std::string result;
  std::string format;
  std::string output;
  ExportOptions frames;
};

void RunExport(const ExportArgs& args) {
  const auto format = ParseExportFormat(args.format);
  if (!format) {
    std::string names;
    for (const auto& n : ExportFormatNames()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("", "", "--to: expected one of " + names + "; got '" + args.format + "'");
  }
  std::string why;
  if (!args.frames.Check(&why)) throw InputError("", "", "invalid frame option: " + why);
  const CalibrationResult result = LoadResult(args.result);
  std::vector<std::string> warnings;
  try {
    ExportResult(result, *format, args.frames, args.result, args.output, &warnings);
  } catch (const InputError& e) {
    throw e.file().empty() ? e.WithFile(args.result) : e;
  }
  PrintWarnings(warnings);
  int cameras = 0;
  for (const auto& camera : result.cameras) cameras += camera.calibrated ? 1 : 0;
  std::cerr << "wrote " << args.output << " (" << ExportFormatName(*format) << ": " << cameras
            << " cameras and the target, parent frame "
            << (result.setup == Setup::kEyeToHand ? args.frames.base_frame : args.frames.ee_frame) << ")\n";
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
  cmd->callback([args]() { RunExport(*args); });
}

HANDEYE_SUBCOMMAND(90, RegisterExport);

}  // namespace handeye::tools
