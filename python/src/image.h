// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Images from numpy arrays, and the target's detector run on one.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>

#include "handeye/core/target.h"
#include "handeye/detectors/detector.h"

namespace handeye::python {

namespace py = pybind11;

/// An 8-bit grey view of an image array: H×W, H×W×3 (BGR, OpenCV's order) or
/// H×W×4 (BGRA), uint8 or uint16 (scaled by 1/257, as image files are). Grey
/// uint8 arrays are used in place; `keep` holds the array alive for `mat`.
struct GrayImage {
  GrayImage(py::handle image, const std::string& where);
  py::array keep;
  cv::Mat mat;
};

/// The target's detector on the image, with the GIL released; nullopt when
/// the target is not found.
std::optional<Detection> DetectIn(const GrayImage& image,
                                  const std::shared_ptr<const Target>& target);

}  // namespace handeye::python
