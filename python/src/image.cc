// SPDX-License-Identifier: GPL-2.0-or-later
#include "image.h"

#include <opencv2/imgproc.hpp>

#include "handeye/core/error.h"
#include "handeye/detectors/registry.h"
#include "progress.h"

namespace handeye::python {

GrayImage::GrayImage(py::handle image, const std::string& where) {
  const std::string expected =
      "an image array: H×W, H×W×3 (BGR) or H×W×4 (BGRA) of uint8 or uint16";
  if (!py::isinstance<py::array>(image)) throw InputError("", where, "expected " + expected);
  py::array a = py::reinterpret_borrow<py::array>(image);
  const bool u8 = a.dtype().kind() == 'u' && a.itemsize() == 1;
  const bool u16 = a.dtype().kind() == 'u' && a.itemsize() == 2;
  const int channels = a.ndim() == 2 ? 1 : a.ndim() == 3 ? static_cast<int>(a.shape(2)) : 0;
  if ((!u8 && !u16) || (channels != 1 && channels != 3 && channels != 4) || a.shape(0) < 1 ||
      a.shape(1) < 1 || a.shape(0) > (1 << 16) || a.shape(1) > (1 << 16))
    throw InputError("", where,
                     "expected " + expected + ", got dtype " + std::string(py::str(a.dtype())) +
                         " with " + std::to_string(a.ndim()) + " dimensions");
  // A C-contiguous copy when the array is a strided view (a crop, a channel).
  keep = u8 ? py::array(
                  py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(a))
            : py::array(
                  py::array_t<std::uint16_t, py::array::c_style | py::array::forcecast>::ensure(a));
  const int type = CV_MAKETYPE(u8 ? CV_8U : CV_16U, channels);
  cv::Mat view(static_cast<int>(keep.shape(0)), static_cast<int>(keep.shape(1)), type,
               const_cast<void*>(keep.data()));  // read only: Detect() takes it const
  if (channels == 3) cv::cvtColor(view, view, cv::COLOR_BGR2GRAY);
  if (channels == 4) cv::cvtColor(view, view, cv::COLOR_BGRA2GRAY);
  if (u16) view.convertTo(view, CV_8U, 1.0 / 257.0);
  mat = view;
}

std::optional<Detection> DetectIn(const GrayImage& image,
                                  const std::shared_ptr<const Target>& target) {
  const std::unique_ptr<Detector> detector = MakeDetector(target);
  return WithoutGil([&] { return detector->Detect(image.mat); });
}

}  // namespace handeye::python
