// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Image files in and out (any format OpenCV reads; PNG out).

#include <opencv2/core/mat.hpp>
#include <string>

#include "handeye/core/camera.h"

namespace handeye {

/// Loads an image as 8-bit grey (colour is converted, 16-bit is scaled).
/// Throws InputError naming the path when it is missing or unreadable, or its
/// size differs from the camera's `image_size`.
cv::Mat LoadGrayImage(const std::string& path, const Camera& camera);

/// Opt-in, process-wide: lets glibc keep freed blocks of up to 64 MB for
/// reuse instead of returning them to the kernel. Image work (OpenCV's
/// checkerboard detector, the renderer, the report) allocates and frees
/// blocks of several MB per image; by default glibc unmaps them on free and
/// the next image faults the same pages in again, which on METRIC's synthetic
/// cell was 1.6 s of 19.7 s detection CPU. The handeye program calls this at
/// start; the libraries never do, as it changes the allocator for the whole
/// process (freed memory, a few hundred MB at most, then stays with it). No
/// effect without glibc.
void ReuseFreedImageMemory();

/// Writes a PNG atomically; throws InputError naming the path on failure.
void WritePng(const std::string& path, const cv::Mat& image);

}  // namespace handeye
