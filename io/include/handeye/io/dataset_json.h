// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Reading and writing `handeye-dataset/1`, `handeye-observations/1` (SPEC §4,
/// §5) and `handeye-ground-truth/1`. Every loader throws InputError naming the
/// file, the JSON path and what was expected; it never fills in a silent
/// default. Writers are atomic (io/atomic_file.h).
///
/// Besides the 4×4 array of SPEC §4, `T_base_ee` may be a pose object
/// (io/pose_formats.h: translation in m or mm, quaternion in either order,
/// rotation vector or Euler angles), and a camera may give `intrinsics_file`
/// instead of `intrinsics` and `distortion` (io/intrinsics_files.h: OpenCV,
/// ROS camera_info, Kalibr camchain). The writers always write the explicit
/// form (4×4 arrays, intrinsics in numbers).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "handeye/core/dataset.h"
#include "handeye/core/warning.h"

namespace handeye {

/// How LoadDataset() treats robot rotations.
struct LoadOptions {
  /// Replace a slightly non-orthonormal rotation in T_base_ee by the nearest
  /// rotation instead of rejecting it.
  bool reorthonormalise = false;
};

/// Reads a dataset or an observations file (told apart by `format`). Image
/// paths come back resolved against the file's folder. Target warnings (e.g.
/// an ambiguous checkerboard) are appended to `warnings` when given.
Dataset LoadDataset(const std::string& path, const LoadOptions& options = {},
                    std::vector<Warning>* warnings = nullptr);

/// The same for a document already parsed, e.g. assembled in memory. `path`
/// names it in error messages and anchors relative paths (images, intrinsics
/// files); it need not exist.
Dataset DatasetFromJson(const nlohmann::json& document, const std::string& path,
                        const LoadOptions& options = {}, std::vector<Warning>* warnings = nullptr);

/// Writes `handeye-dataset/1`; image paths are written relative to the file's folder.
void SaveDataset(const Dataset& dataset, const std::string& path);

class JsonReader;
/// A camera's "intrinsics" and "distortion" in the dataset's form (SPEC §4),
/// set on `object` (the result file uses them for refined intrinsics too).
void WriteIntrinsicsJson(const Camera& camera, nlohmann::ordered_json* object);
/// Reads "intrinsics" and "distortion" of `object` (that form) into a camera
/// of the given name and size; throws InputError naming the key.
Camera ReadIntrinsicsJson(const JsonReader& object, const std::string& name, int width, int height);
/// Writes `handeye-observations/1` (no images, with observations).
void SaveObservations(const Dataset& dataset, const std::string& path);

/// Reads `ground_truth.json` (or a dataset's `ground_truth` object).
GroundTruth LoadGroundTruth(const std::string& path);
/// Writes `handeye-ground-truth/1`, with the simulator's per-pose truth if any.
void SaveGroundTruth(const GroundTruth& truth, const std::string& path);

}  // namespace handeye
