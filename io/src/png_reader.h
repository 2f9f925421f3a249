// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// PNG input through libspng, the common files inflated by libdeflate (see
// png_reader.cc): every PNG form (1 to 16 bits, grey, colour, palette,
// alpha, interlaced) without going through OpenCV, whose libpng
// prints its own "libpng error: ..." on stderr for a damaged file, and with
// the image size checked from the header before any pixel memory is
// allocated. Internal to the io library.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <opencv2/core/mat.hpp>
#include <string>

namespace handeye::internal {

/// Called with the header's width and height before the pixels are decoded;
/// throws (InputError) to refuse the size.
using PngSizeCheck = std::function<void(std::uint32_t width, std::uint32_t height)>;

/// True when `size` bytes at `data` start with the 8-byte PNG signature.
bool HasPngSignature(const std::uint8_t* data, std::size_t size);

/// Decodes a whole PNG file held in memory to 8-bit grey, as LoadGrayImage
/// gives every image: colour converted with OpenCV's weights (alpha dropped,
/// as cv::imread drops it), 16-bit scaled by 1/257. Pixel for pixel what
/// cv::imread and that conversion give (tested). `path` names the file in
/// errors. Throws InputError(path, "", ...) for a damaged or truncated file
/// (libspng checks chunk CRCs and the zlib checksum), and whatever
/// `check_size` throws.
cv::Mat DecodePngGray(const std::uint8_t* data, std::size_t size, const std::string& path,
                      const PngSizeCheck& check_size);

}  // namespace handeye::internal
