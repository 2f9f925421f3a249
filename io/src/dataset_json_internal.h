// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// What the dataset reader (dataset_json.cc) and the ground-truth reader
// (ground_truth_json.cc) share.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "handeye/core/dataset.h"
#include "handeye/core/target.h"
#include "handeye/io/json_util.h"

namespace handeye::internal {

inline constexpr char kDatasetFormat[] = "handeye-dataset/1";
inline constexpr char kObservationsFormat[] = "handeye-observations/1";
inline constexpr char kGroundTruthFormat[] = "handeye-ground-truth/1";

/// "eye_to_hand" or "eye_in_hand", else an InputError naming the JSON path.
Setup ReadSetup(const JsonReader& r);

/// `ids` and pixels of one view; ids unique and >= 0. `target` (may be null)
/// additionally requires every id to be one of its points.
void ReadIdsAndPixels(const JsonReader& ids_json, const JsonReader& px_json, const Target* target,
                      Observation* view);

/// [[u, v], ...] of points in pixels.
nlohmann::ordered_json PixelsJson(const std::vector<Eigen::Vector2d>& points);

/// A ground-truth object: a whole handeye-ground-truth/1 file, or a dataset's
/// `ground_truth` object (then `dataset_setup` is the dataset's and the object
/// may leave out `format` and `setup`).
GroundTruth ReadGroundTruth(const JsonReader& r, std::optional<Setup> dataset_setup);

}  // namespace handeye::internal
