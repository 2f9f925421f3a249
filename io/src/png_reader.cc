// SPDX-License-Identifier: GPL-2.0-or-later
#include "png_reader.h"

#include <spng.h>

#include <array>
#include <cstring>
#include <memory>
#include <new>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "handeye/core/error.h"

// Why libspng rather than a decoder of our own (issue 15): until then
// handeye decoded 8-bit non-interlaced PNG itself (170 lines on libdeflate)
// and left the rest to OpenCV. Measured on 23 Nov 2026 on the shared 2-core
// VM (other builds running, so CPU time of the process, not wall time; one
// thread, cv::setNumThreads(1)), per image, decode + conversion to grey, and
// the whole detect stage (read, decode, grey, the checkerboard detector):
//
//   images                                  decoder       decode   detect stage
//   METRIC medium_workcell, 1920x1080 RGB   own           22.4 ms   457 ms
//   (40 of camera1..4, 16 with the board)   libspng 0.7.3 34.6 ms   471 ms
//                                           libpng (cv)   30.7 ms   441 ms
//   `handeye simulate --poses 20`,          own           11.9 ms   157 ms
//   1920x1080 grey (32 views)               libspng 0.7.3 20.7 ms   190 ms
//                                           libpng (cv)   16.3 ms   168 ms
//
// The own decoder was 1.03x (METRIC) and 1.21x (simulator) faster on the
// whole detect stage, under the 1.3x that would justify a parser of our
// own to maintain and fuzz, so libspng reads every PNG. It also never
// prints to stderr (OpenCV's libpng printed "libpng error: Read Error" for a
// truncated file) and lets the header's size be checked before decoding.

namespace handeye::internal {
namespace {

// Ancillary chunks libspng keeps (text, ICC profile, EXIF) are capped at
// 16 MB together; handeye uses none of them.
constexpr std::size_t kChunkCacheLimit = std::size_t{16} << 20;

struct ContextDeleter {
  void operator()(spng_ctx* ctx) const { spng_ctx_free(ctx); }
};

InputError Damaged(const std::string& path, int error) {
  std::string why = spng_strerror(error);
  if (error == SPNG_IO_EOF || error == SPNG_EOF || error == SPNG_EIDAT_TOO_SHORT) why = "the file ends too early (truncated)";
  return InputError(path, "", "damaged PNG: " + why + "; expected a complete PNG file");
}

}  // namespace

bool HasPngSignature(const std::uint8_t* data, std::size_t size) {
  static constexpr std::array<std::uint8_t, 8> kSignature = {137, 80, 78, 71, 13, 10, 26, 10};
  return size >= kSignature.size() && std::memcmp(data, kSignature.data(), kSignature.size()) == 0;
}

cv::Mat DecodePngGray(const std::uint8_t* data, std::size_t size, const std::string& path,
                      const PngSizeCheck& check_size) {
  std::unique_ptr<spng_ctx, ContextDeleter> ctx(spng_ctx_new(0));
  if (!ctx) throw std::bad_alloc();
  // No chunk can be longer than the file; this also keeps libspng from
  // allocating for a length field that lies.
  int error = spng_set_chunk_limits(ctx.get(), size, kChunkCacheLimit);
  if (!error) error = spng_set_png_buffer(ctx.get(), data, size);
  spng_ihdr header{};
  if (!error) error = spng_get_ihdr(ctx.get(), &header);
  if (error) throw Damaged(path, error);
  // libspng has refused sides over 2^31 - 1, so they fit an int.
  check_size(header.width, header.height);

  // The output format closest to the file's own, so libspng converts little:
  // grey stays grey; colour, palette and grey + alpha become RGB; 16-bit
  // anything becomes RGBA16 (host byte order).
  int format = SPNG_FMT_RGB8, type = CV_8UC3, to_grey = cv::COLOR_RGB2GRAY;
  if (header.bit_depth == 16) {
    format = SPNG_FMT_RGBA16;
    type = CV_16UC4;
    to_grey = cv::COLOR_RGBA2GRAY;
  } else if (header.color_type == SPNG_COLOR_TYPE_GRAYSCALE) {
    format = SPNG_FMT_G8;
    type = CV_8UC1;
    to_grey = -1;
  }
  std::size_t bytes = 0;
  error = spng_decoded_image_size(ctx.get(), format, &bytes);
  if (error) throw Damaged(path, error);
  cv::Mat image(static_cast<int>(header.height), static_cast<int>(header.width), type);
  if (bytes != image.total() * image.elemSize())
    throw std::logic_error("libspng wants " + std::to_string(bytes) + " bytes for " + path);
  error = spng_decode_image(ctx.get(), image.data, bytes, format, 0);
  if (error) throw Damaged(path, error);
  if (to_grey >= 0) cv::cvtColor(image, image, to_grey);
  if (image.depth() == CV_16U) image.convertTo(image, CV_8U, 1.0 / 257.0);
  return image;
}

}  // namespace handeye::internal
