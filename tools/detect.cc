// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye detect DATASET -o OBS.json`: runs the target's detector on every
// image and writes handeye-observations/1 (SPEC §5, §7).
#include <iostream>
#include <map>
#include <memory>

#include "cli_numbers.h"
#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/detection.h"
#include "handeye/io/repeated_images.h"
#include "output_paths.h"

namespace handeye::tools {
namespace {

struct DetectArgs {
  bool quiet = false;  // --quiet: no progress line
  std::string dataset;
  std::string output;
  int threads = 0;
  bool reorthonormalise = false;
};

void RunDetect(const DetectArgs& args) {
  LoadOptions load;
  load.reorthonormalise = args.reorthonormalise;
  std::vector<Warning> warnings;
  Dataset dataset = LoadDataset(args.dataset, load, &warnings);
  PrintWarnings(warnings);
  // Before minutes of detection: the output can be written and is no input.
  std::vector<NamedPath> inputs = ImageInputs(dataset);
  inputs.push_back({"DATASET", args.dataset});
  CheckFileOutputs(inputs, {{"-o", args.output}});

  std::map<std::string, int> images_per_camera;
  for (const auto& pose : dataset.poses)
    for (const auto& [camera, image] : pose.images) ++images_per_camera[camera];
  if (images_per_camera.empty())
    throw InputError(args.dataset, "/poses",
                     "no images to detect in; expected a handeye-dataset/1 file whose poses list "
                     "images");

  DetectOptions options;
  options.threads = args.threads;
  options.progress = ProgressLine("detecting", args.quiet);
  PrintWarnings(RepeatedImageWarnings(dataset));
  const std::vector<Warning> detect_warnings = DetectAll(&dataset, options);

  std::map<std::string, int> found_per_camera;
  for (const auto& view : dataset.observations) ++found_per_camera[view.camera];
  for (const auto& camera : dataset.cameras)
    std::cerr << camera.name << ": " << images_per_camera[camera.name]
              << " images, target found in " << found_per_camera[camera.name] << "\n";
  PrintWarnings(detect_warnings);
  SaveObservations(dataset, args.output);
  std::cerr << "wrote " << args.output << " (" << dataset.observations.size() << " views)\n";
}

}  // namespace

void RegisterDetect(CLI::App& app) {
  auto args = std::make_shared<DetectArgs>();
  CLI::App* cmd =
      app.add_subcommand("detect", "run the target's detector on every image of a dataset");
  cmd->add_option("DATASET", args->dataset, "handeye-dataset/1 file")->required();
  cmd->add_option("-o,--output", args->output,
                  "observations file to write (handeye-observations/1)")
      ->required();
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(ThreadCount());
  cmd->add_flag("--reorthonormalise", args->reorthonormalise,
                "replace slightly non-orthonormal robot rotations by the nearest rotation");
  AddQuietFlag(cmd, &args->quiet);
  cmd->callback([args]() { RunDetect(*args); });
}

HANDEYE_SUBCOMMAND(10, RegisterDetect);

}  // namespace handeye::tools
