// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/image.h"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <vector>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "handeye/core/error.h"
#include "handeye/core/input_limits.h"
#include "handeye/io/atomic_file.h"
#include "png_reader.h"

namespace handeye {

namespace {

InputError SizeMismatch(const std::string& path, const Camera& camera, std::uint64_t width,
                        std::uint64_t height) {
  return InputError(path, "",
                    "image is " + std::to_string(width) + "x" + std::to_string(height) +
                        " but camera '" + camera.name + "' has image_size [" +
                        std::to_string(camera.width) + ", " + std::to_string(camera.height) + "]");
}

/// The whole file, as bytes.
std::vector<std::uint8_t> ReadBytes(const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!file) throw InputError(path, "", std::string("cannot read the image: ") + std::strerror(errno));
  std::vector<std::uint8_t> bytes;
  std::uint8_t buffer[1 << 16];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, file.get())) > 0;)
    bytes.insert(bytes.end(), buffer, buffer + n);
  if (std::ferror(file.get())) throw InputError(path, "", "cannot read the image: read error");
  return bytes;
}

}  // namespace

cv::Mat LoadGrayImage(const std::string& path, const Camera& camera) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path, "", "image file does not exist (camera '" + camera.name + "')");
  // Before the file is read: the image must have the camera's size.
  RequireImagePixelsWithinLimit(camera.width, camera.height, path, "");
  const std::vector<std::uint8_t> bytes = ReadBytes(path);
  if (internal::HasPngSignature(bytes.data(), bytes.size())) {
    // The size is checked from the header, before any pixel memory exists:
    // a header that claims 65536 x 65536 pixels costs nothing.
    return internal::DecodePngGray(bytes.data(), bytes.size(), path,
                                   [&](std::uint32_t width, std::uint32_t height) {
                                     if (width != static_cast<std::uint32_t>(camera.width) ||
                                         height != static_cast<std::uint32_t>(camera.height))
                                       throw SizeMismatch(path, camera, width, height);
                                   });
  }
  // Other formats (JPEG, TIFF, ...) through OpenCV, which checks their
  // headers against its own pixel limit before decoding.
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  } catch (const cv::Exception& e) {
    throw InputError(path, "", "unreadable image (" + e.err + "): expected a PNG, JPEG or TIFF file");
  }
  if (image.empty())
    throw InputError(path, "", "unreadable image: expected a PNG, JPEG or TIFF file");
  if (image.cols != camera.width || image.rows != camera.height)
    throw SizeMismatch(path, camera, image.cols, image.rows);
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
