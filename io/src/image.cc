// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/image.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "handeye/core/error.h"
#include "handeye/io/atomic_file.h"
#include "png_reader.h"

namespace handeye {

cv::Mat LoadGrayImage(const std::string& path, const Camera& camera) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path, "", "image file does not exist (camera '" + camera.name + "')");
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  std::optional<cv::Mat> fast;
  if (extension == ".png") fast = internal::ReadPng8(path);
  cv::Mat image =
      fast ? std::move(*fast) : cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  if (image.empty())
    throw InputError(path, "", "unreadable image: expected a PNG, JPEG or TIFF file");
  if (image.cols != camera.width || image.rows != camera.height)
    throw InputError(path, "",
                     "image is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                         " but camera '" + camera.name + "' has image_size [" +
                         std::to_string(camera.width) + ", " + std::to_string(camera.height) + "]");
  if (image.channels() == 3) {
    cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, image, cv::COLOR_BGRA2GRAY);
  }
  if (image.depth() == CV_16U) {
    image.convertTo(image, CV_8U, 1.0 / 257.0);
  } else if (image.depth() != CV_8U) {
    double lo = 0, hi = 0;
    cv::minMaxLoc(image, &lo, &hi);
    image.convertTo(image, CV_8U, hi > lo ? 255.0 / (hi - lo) : 1.0, hi > lo ? -lo * 255.0 / (hi - lo) : 0.0);
  }
  return image;
}

void ReuseFreedImageMemory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

void WritePng(const std::string& path, const cv::Mat& image) {
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", image, bytes)) throw InputError(path, "", "cannot encode PNG");
  WriteFileAtomically(path, std::string(bytes.begin(), bytes.end()));
}

}  // namespace handeye
