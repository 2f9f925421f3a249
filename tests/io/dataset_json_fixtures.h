// SPDX-License-Identifier: GPL-2.0-or-later
// The dataset and observation files the dataset_json tests start from, and
// the check that a bad one is refused with the file, the JSON path and what
// was expected.
#pragma once

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "handeye/core/error.h"
#include "handeye/io/dataset_json.h"
#include "support/input_error.h"
#include "support/test_support.h"

namespace handeye::test {

using Catch::Matchers::Contains;
using nlohmann::json;


inline json ValidDatasetJson() {
  return json::parse(R"({
    "format": "handeye-dataset/1",
    "setup": "eye_to_hand",
    "target": {"type": "checkerboard", "inner_corners": [4, 3], "square_size_m": 0.05},
    "cameras": [
      {"name": "cam0", "image_size": [1920, 1080],
       "intrinsics": {"fx": 1371.0, "fy": 1371.0, "cx": 960.5, "cy": 540.5},
       "distortion": {"model": "none"}},
      {"name": "cam1", "image_size": [640, 480],
       "intrinsics": {"fx": 500, "fy": 501, "cx": 320, "cy": 240},
       "distortion": {"model": "opencv", "coeffs": [0.1, -0.2, 0.001, 0.002, 0.05]}}
    ],
    "poses": [
      {"id": "0001", "T_base_ee": [[1,0,0,0.4],[0,1,0,0.1],[0,0,1,0.9],[0,0,0,1]],
       "images": {"cam0": "cam0/0001.png", "cam1": "cam1/0001.png"}},
      {"id": "0002", "T_base_ee": [[0,-1,0,0.4],[1,0,0,0.1],[0,0,1,0.9],[0,0,0,1]],
       "images": {"cam0": "cam0/../cam0/0002.png"}},
      {"id": "0003", "T_base_ee": [[1,0,0,0],[0,0,-1,0],[0,1,0,0.5],[0,0,0,1]],
       "images": {"cam1": "/data/elsewhere/0003.png"}}
    ]
  })");
}

inline json ValidObservationsJson() {
  json j = ValidDatasetJson();
  j["format"] = "handeye-observations/1";
  for (auto& pose : j["poses"]) pose.erase("images");
  j["observations"] = json::parse(R"([
    {"pose": "0001", "camera": "cam0", "ids": [0, 1, 2], "points_px": [[1, 2], [3, 4], [5.5, 6.25]]},
    {"pose": "0001", "camera": "cam1", "ids": [11, 5], "points_px": [[10, 20], [30, 40]]},
    {"pose": "0002", "camera": "cam0", "ids": [3], "points_px": [[7, 8]]}
  ])");
  return j;
}

inline std::string WriteJson(const std::string& path, const json& j) {
  WriteText(path, j.dump(2));
  return path;
}

// Loads `j` from a file and requires an InputError at `json_path` whose
// message says `expected`; the message must start with "<file>: at <path>: ".
inline void RequireLoadError(const json& j, const std::string& json_path, const std::string& expected,
                             const LoadOptions& options = {}) {
  const std::string file = WriteJson(TempDir("dataset_bad") + "/data.json", j);
  RequireInputErrorAt(file, json_path, expected, [&] { LoadDataset(file, options); });
}

}  // namespace handeye::test
