// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye evaluate RESULT GROUND_TRUTH [--json]`: the paper's e_t^GT (mm) and
// e_θ^GT (deg) per camera and their mean.
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "argument_order.h"
#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/core/evaluation.h"
#include "handeye/core/setup_frames.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/result_json.h"

namespace handeye::tools {
namespace {

struct EvaluateArgs {
  std::string result;
  std::string truth;
  bool json = false;
};

void RunEvaluate(const EvaluateArgs& args) {
  CheckArgumentOrder(
      "handeye evaluate RESULT GROUND_TRUTH",
      {{"RESULT", args.result, {"handeye-result/1"}},
       {"GROUND_TRUTH", args.truth, {"handeye-ground-truth/1", "handeye-dataset/1"}}});
  const CalibrationResult result = LoadResult(args.result);
  const GroundTruth truth = LoadGroundTruth(args.truth);
  Evaluation eval;
  try {
    eval = EvaluateAgainstTruth(result, truth);
  } catch (const InputError& e) {
    throw e.WithFile(args.truth);
  }
  for (const auto& name : eval.missing)
    std::cerr << "warning: camera '" << name << "' not compared (not calibrated or no ground truth)\n";
  if (args.json) {
    nlohmann::ordered_json out;
    out["method"] = MethodName(result.method);
    for (const auto& c : eval.cameras)
      out["cameras"][c.name] = {{"translation_mm", c.translation_mm}, {"rotation_deg", c.rotation_deg}};
    out["mean_translation_mm"] = eval.mean_translation_mm;
    out["mean_rotation_deg"] = eval.mean_rotation_deg;
    if (eval.has_target_error)
      out["target"] = {{"translation_mm", eval.target_translation_mm}, {"rotation_deg", eval.target_rotation_deg}};
    std::cout << out.dump(2) << "\n";
    return;
  }
  std::printf("%-12s %12s %12s\n", "camera", "e_t^GT mm", "e_theta^GT deg");
  for (const auto& c : eval.cameras) std::printf("%-12s %12.3f %12.4f\n", c.name.c_str(), c.translation_mm, c.rotation_deg);
  std::printf("%-12s %12.3f %12.4f\n", "mean", eval.mean_translation_mm, eval.mean_rotation_deg);
  if (eval.has_target_error)
    std::printf("%-12s %12.3f %12.4f\n", FramesOf(result.setup).target_key.c_str(),
                eval.target_translation_mm, eval.target_rotation_deg);
}

}  // namespace

void RegisterEvaluate(CLI::App& app) {
  auto args = std::make_shared<EvaluateArgs>();
  CLI::App* cmd = app.add_subcommand("evaluate", "errors of a result against ground truth");
  cmd->add_option("RESULT", args->result, "handeye-result/1 file")->required();
  cmd->add_option("GROUND_TRUTH", args->truth, "ground_truth.json")->required();
  cmd->add_flag("--json", args->json, "print JSON instead of a table");
  cmd->callback([args]() { RunEvaluate(*args); });
}

HANDEYE_SUBCOMMAND(40, RegisterEvaluate);

}  // namespace handeye::tools
