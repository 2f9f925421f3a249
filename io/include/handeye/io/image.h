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

/// Writes a PNG atomically; throws InputError naming the path on failure.
void WritePng(const std::string& path, const cv::Mat& image);

}  // namespace handeye
