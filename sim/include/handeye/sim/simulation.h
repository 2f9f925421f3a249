// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// A synthetic scene rendered to disk as a dataset (`handeye simulate`).

#include <cstddef>
#include <functional>
#include <string>

#include "handeye/sim/render.h"
#include "handeye/sim/synthetic.h"

namespace handeye {

/// Renders the scene's views (every camera at every pose, or with
/// `render.every_view` false only those in which the target is visible) and writes
/// OUTDIR/dataset.json, OUTDIR/ground_truth.json and OUTDIR/images/<camera>/<pose>.png.
/// Fills scene->dataset.poses[*].images. `progress(done, total)` after each image.
/// Each image gets its own noise/background seed derived from `render.seed`
/// and the view, so the files do not depend on `threads`; camera k's blur is
/// `render.blur_sigma_px` times a per-camera factor in [2/3, 4/3] (lenses
/// differ), also fixed by `render.seed`, unless `render.camera_quality` names it.
void WriteSimulation(SyntheticScene* scene, const RenderOptions& render, const std::string& outdir,
                     int threads = 0,
                     const std::function<void(std::size_t, std::size_t)>& progress = {});

/// Renders the scene's views (as WriteSimulation) in memory and runs the
/// target's detector on each, replacing scene->dataset.observations with what was found
/// (pose then camera order). The same images as WriteSimulation, without the
/// PNG round trip: for benchmarks and tests that need detections, not files.
void DetectSimulated(SyntheticScene* scene, const RenderOptions& render, int threads = 0,
                     const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace handeye
