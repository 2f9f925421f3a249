// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A fast path for the images handeye reads most: 8-bit, non-interlaced PNG.
// Internal to the io library.

#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>

namespace handeye::internal {

/// The PNG file at `path` as an 8-bit image of 1 (grey) or 3 (BGR; alpha is
/// dropped) channels, decoded with libdeflate, or nullopt when this reader does not
/// handle the file: not a PNG, 16-bit or palette colour, interlaced, a
/// transparency chunk, a damaged stream, or handeye built without libdeflate.
/// The caller then reads the file with OpenCV, which also reports what is
/// wrong with it. For the files it does decode the result is the one
/// cv::imread gives (tested), in about half libpng's time: on 1920x1080
/// greyscale images libpng's inflate took 11 ms of CPU per image.
std::optional<cv::Mat> ReadPng8(const std::string& path);

/// True when handeye was built with libdeflate, i.e. ReadPng8 decodes.
bool HaveFastPngReader();

}  // namespace handeye::internal
