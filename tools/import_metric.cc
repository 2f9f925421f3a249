// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye import-metric FOLDER -o DATASET.json`: converts a folder in the
// METRIC / original-tool layout (SPEC §8) into handeye-dataset/1, plus
// ground_truth.json beside it when the folder has GT/.
#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/metric_import.h"
#include "output_paths.h"

namespace handeye::tools {
namespace {

struct ImportMetricArgs {
  std::string folder;
  std::string output;
};

// The files import-metric reads (SPEC §8) are all inside FOLDER: an output
// there may be a new file, never one that exists.
std::vector<NamedPath> FilesIn(const std::string& folder) {
  std::vector<NamedPath> files;
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(folder, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec))
    if (it->is_regular_file(ec)) files.push_back({"FOLDER's file", it->path().string()});
  return files;
}

std::string TruthPathBeside(const std::string& output) {
  return (std::filesystem::path(output).parent_path() / "ground_truth.json").string();
}

void RunImportMetric(const ImportMetricArgs& args) {
  CheckFileOutputs(
      FilesIn(args.folder),
      {{"-o", args.output}, {"ground_truth.json beside -o", TruthPathBeside(args.output)}});
  const MetricImport imported = ImportMetricFolder(args.folder);
  PrintWarnings(imported.dataset.target->Warnings());
  PrintWarnings(imported.warnings);
  for (const std::string& note : imported.notes) std::cerr << "note: " << note << "\n";
  std::size_t images = 0;
  for (const auto& pose : imported.dataset.poses) images += pose.images.size();
  SaveDataset(imported.dataset, args.output);
  std::cerr << "wrote " << args.output << ": " << imported.dataset.cameras.size() << " cameras, "
            << imported.dataset.poses.size() << " poses, " << images << " images, setup "
            << SetupName(imported.dataset.setup) << "\n";
  if (imported.truth) {
    const std::string truth_path = TruthPathBeside(args.output);
    SaveGroundTruth(*imported.truth, truth_path);
    std::cerr << "wrote " << truth_path << " (camera poses; the target pose is not in GT/)\n";
  }
}

}  // namespace

void RegisterImportMetric(CLI::App& app) {
  auto args = std::make_shared<ImportMetricArgs>();
  CLI::App* cmd = app.add_subcommand(
      "import-metric", "convert a folder in the METRIC / original-tool layout to a dataset");
  cmd->add_option("FOLDER", args->folder, "folder with CalibrationInfo.yaml and camera<k>/")
      ->required();
  cmd->add_option("-o,--output", args->output, "dataset file to write (handeye-dataset/1)")
      ->required();
  cmd->callback([args]() { RunImportMetric(*args); });
}

HANDEYE_SUBCOMMAND(60, RegisterImportMetric);

}  // namespace handeye::tools
