// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Caps on what an input may declare, checked before any memory is set aside
/// for it: a board declared 20000 x 20000 asked for 12.5 GB of target points,
/// a PNG header declaring 65536 x 65536 pixels for 9.5 GB of image.
///
/// The defaults lie far above real equipment and far below what a machine
/// runs out on:
/// - kDefaultMaxTargetPoints, 20 000 corners: the densest printed boards
///   (1 m ChArUco with 10 mm squares, 99 x 99 = 9 801 corners) stay under
///   half of it, and 20 000 points take under a megabyte.
/// - kDefaultMaxImagePixels, 200 Mpx: above the largest machine-vision
///   sensors (Sony IMX411, 151 Mpx); one grey image of it is 200 MB.
///
/// SetMaxTargetPoints / SetMaxImagePixels (the command line's
/// --max-target-points and --max-image-pixels) raise or lower them for the
/// process; where those were not called, the environment variables
/// HANDEYE_MAX_TARGET_POINTS and HANDEYE_MAX_IMAGE_PIXELS (a positive
/// integer; 3e8 is read as 300000000) do, read at each check.

#include <cstdint>
#include <string>

namespace handeye {

/// Default largest number of points (corners) one target may have.
constexpr std::int64_t kDefaultMaxTargetPoints = 20000;
/// Default largest width x height of one image or camera.
constexpr std::int64_t kDefaultMaxImagePixels = 200000000;

/// The cap in force: what SetMaxTargetPoints set, else
/// HANDEYE_MAX_TARGET_POINTS, else the default. Throws InputError naming the
/// variable when it is set but not a positive integer.
std::int64_t MaxTargetPoints();
/// The cap in force: what SetMaxImagePixels set, else
/// HANDEYE_MAX_IMAGE_PIXELS, else the default. Throws like MaxTargetPoints.
std::int64_t MaxImagePixels();

/// Sets the cap for the rest of the process, over the environment variable.
/// Throws InputError unless `points` >= 1.
void SetMaxTargetPoints(std::int64_t points);
/// Sets the cap for the rest of the process, over the environment variable.
/// Throws InputError unless `pixels` >= 1.
void SetMaxImagePixels(std::int64_t pixels);

/// Throws InputError("", json_path, ...) when a target of `cols` x `rows`
/// points (computed in 64 bits) exceeds MaxTargetPoints(), naming the count,
/// the cap and the variable that raises it.
void RequireTargetPointsWithinLimit(std::int64_t cols, std::int64_t rows,
                                    const std::string& json_path);

/// Throws InputError(file, json_path, ...) when a `width` x `height` image
/// exceeds MaxImagePixels(), naming the size, the cap and the variable.
void RequireImagePixelsWithinLimit(std::int64_t width, std::int64_t height, const std::string& file,
                                   const std::string& json_path);

}  // namespace handeye
