// SPDX-License-Identifier: GPL-2.0-or-later
// CPU time per image of detection on a dataset of real or rendered images,
// split into images where the target was found and images without it: on a
// camera network most images do not show the target, so both matter. Images
// are detected one after the other on one thread, each timed with the
// process's CPU clock (decode, then detection).
//
//   bench_detect_images DATASET.json [--observations OBS.json] [--timings T.csv]
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "handeye/io/dataset_json.h"
#include "handeye/io/image.h"
#include "support/bench_support.h"

using namespace handeye;
using namespace handeye::bench;

int main(int argc, char** argv) {
  handeye::ReuseFreedImageMemory();
  CLI::App app{"handeye detection benchmark: CPU ms per image, with and without the target"};
  std::string dataset_path, observations_path, timings_path, json_path;
  app.add_option("DATASET", dataset_path, "handeye-dataset/1 file")->required();
  app.add_option("--observations", observations_path, "also write what was found (handeye-observations/1)");
  app.add_option("--timings", timings_path, "also write one CSV line per image");
  app.add_option("--json", json_path, "also write the summary to this JSON file");
  CLI11_PARSE(app, argc, argv);

  Dataset dataset = LoadDataset(dataset_path);
  const Stopwatch watch;
  const std::vector<ImageTiming> timings = DetectTimed(&dataset);
  const double wall_s = watch.Seconds();

  Table table({"images", "count", "CPU ms/image mean", "median", "90th pct", "max", "of which decode (mean)"});
  nlohmann::ordered_json json;
  for (const bool found : {true, false}) {
    const ClassTiming t = SummariseTimings(timings, found);
    const char* name = found ? "with target" : "without target";
    table.Add({name, std::to_string(t.images), Format("%.1f", t.mean_ms), Format("%.1f", t.median_ms),
               Format("%.1f", t.p90_ms), Format("%.1f", t.max_ms), Format("%.1f", t.mean_load_ms)});
    json[found ? "with_target" : "without_target"] = {
        {"images", t.images}, {"mean_ms", t.mean_ms},   {"median_ms", t.median_ms},
        {"p90_ms", t.p90_ms}, {"max_ms", t.max_ms},     {"mean_decode_ms", t.mean_load_ms}};
  }
  json["wall_s"] = wall_s;
  std::printf("### Detection on %s: %zu images, one thread, %.1f s wall\n\n%s", dataset_path.c_str(),
              timings.size(), wall_s, table.Markdown().c_str());

  if (!observations_path.empty()) SaveObservations(dataset, observations_path);
  if (!timings_path.empty()) {
    std::ofstream csv(timings_path);
    csv << "pose,camera,found,decode_cpu_ms,detect_cpu_ms\n";
    for (const ImageTiming& t : timings)
      csv << t.pose_id << "," << t.camera << "," << (t.found ? 1 : 0) << "," << 1000.0 * t.load_cpu_s << ","
          << 1000.0 * t.detect_cpu_s << "\n";
  }
  if (!json_path.empty()) std::ofstream(json_path) << json.dump(2) << "\n";
  return 0;
}
