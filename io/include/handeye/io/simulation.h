// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "handeye/core/synthetic.h"
#include "handeye/io/render.h"

namespace handeye {

/// Renders every view of the scene in which the target is visible and writes
/// OUTDIR/dataset.json, OUTDIR/ground_truth.json and OUTDIR/images/<camera>/<pose>.png.
/// Fills scene->dataset.poses[*].images. `progress(done, total)` after each image.
void WriteSimulation(SyntheticScene* scene, const RenderOptions& render, const std::string& outdir,
                     int threads = 0,
                     const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace handeye
