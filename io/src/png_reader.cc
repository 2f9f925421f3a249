// SPDX-License-Identifier: GPL-2.0-or-later
#include "png_reader.h"

#if defined(HANDEYE_HAVE_LIBDEFLATE)

#include <libdeflate.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace handeye::internal {
namespace {

std::uint32_t BigEndian32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

/// The whole file, or an empty vector when it cannot be read.
std::vector<std::uint8_t> ReadFile(const std::string& path) {
  std::vector<std::uint8_t> bytes;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!file || std::fseek(file.get(), 0, SEEK_END) != 0) return {};
  const long size = std::ftell(file.get());
  if (size <= 0 || std::fseek(file.get(), 0, SEEK_SET) != 0) return {};
  bytes.resize(static_cast<std::size_t>(size));
  if (std::fread(bytes.data(), 1, bytes.size(), file.get()) != bytes.size()) return {};
  return bytes;
}

/// PNG's Paeth predictor: of left, up and upper-left, the one nearest to
/// left + up - upper-left.
inline int Paeth(int left, int up, int upper_left) {
  const int p = left + up - upper_left;
  const int pa = std::abs(p - left), pb = std::abs(p - up), pc = std::abs(p - upper_left);
  if (pa <= pb && pa <= pc) return left;
  return pb <= pc ? up : upper_left;
}

/// Undoes one row's filter (PNG §9): `raw` (row_bytes) into `out`, with
/// `prev` the row above already unfiltered (zeros above the first row) and
/// `bpp` bytes per pixel. False for an unknown filter type.
bool Unfilter(int type, const std::uint8_t* raw, const std::uint8_t* prev, std::uint8_t* out,
              std::size_t row_bytes, std::size_t bpp) {
  switch (type) {
    case 0:
      std::memcpy(out, raw, row_bytes);
      return true;
    case 1:
      for (std::size_t i = 0; i < row_bytes; ++i)
        out[i] = static_cast<std::uint8_t>(raw[i] + (i >= bpp ? out[i - bpp] : 0));
      return true;
    case 2:
      for (std::size_t i = 0; i < row_bytes; ++i) out[i] = static_cast<std::uint8_t>(raw[i] + prev[i]);
      return true;
    case 3:
      for (std::size_t i = 0; i < row_bytes; ++i) {
        const int left = i >= bpp ? out[i - bpp] : 0;
        out[i] = static_cast<std::uint8_t>(raw[i] + ((left + prev[i]) >> 1));
      }
      return true;
    case 4:
      for (std::size_t i = 0; i < row_bytes; ++i) {
        const int left = i >= bpp ? out[i - bpp] : 0;
        const int upper_left = i >= bpp ? prev[i - bpp] : 0;
        out[i] = static_cast<std::uint8_t>(raw[i] + Paeth(left, prev[i], upper_left));
      }
      return true;
    default:
      return false;
  }
}

struct DecompressorDeleter {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

}  // namespace

std::optional<cv::Mat> ReadPng8(const std::string& path) {
  const std::vector<std::uint8_t> file = ReadFile(path);
  static constexpr std::array<std::uint8_t, 8> kSignature = {137, 80, 78, 71, 13, 10, 26, 10};
  if (file.size() < kSignature.size() ||
      std::memcmp(file.data(), kSignature.data(), kSignature.size()) != 0)
    return std::nullopt;

  std::uint32_t width = 0, height = 0;
  int channels = 0;
  bool header = false, end = false;
  std::vector<std::uint8_t> compressed;
  for (std::size_t at = kSignature.size(); !end;) {
    // Chunk: length, type, data, CRC of type and data.
    if (file.size() - at < 12) return std::nullopt;
    const std::uint32_t length = BigEndian32(&file[at]);
    if (length > file.size() - at - 12) return std::nullopt;
    const std::uint8_t* type = &file[at + 4];
    const std::uint8_t* data = type + 4;
    const bool critical = (type[0] & 0x20) == 0;
    const bool is_header = std::memcmp(type, "IHDR", 4) == 0;
    const bool is_data = std::memcmp(type, "IDAT", 4) == 0;
    end = std::memcmp(type, "IEND", 4) == 0;
    if ((is_header || is_data) && libdeflate_crc32(0, type, length + 4) != BigEndian32(data + length))
      return std::nullopt;
    if (is_header) {
      if (header || length != 13) return std::nullopt;
      width = BigEndian32(data);
      height = BigEndian32(data + 4);
      const int depth = data[8], colour = data[9];
      // Deflate compression, adaptive filtering, no interlacing.
      if (depth != 8 || data[10] != 0 || data[11] != 0 || data[12] != 0) return std::nullopt;
      channels = colour == 0 ? 1 : colour == 2 ? 3 : colour == 6 ? 4 : 0;
      if (channels == 0 || width == 0 || height == 0 || width > (1u << 16) || height > (1u << 16))
        return std::nullopt;
      header = true;
    } else if (!header) {
      return std::nullopt;  // IHDR comes first
    } else if (is_data) {
      compressed.insert(compressed.end(), data, data + length);
    } else if (std::memcmp(type, "tRNS", 4) == 0 || (critical && !end)) {
      // Transparency or a critical chunk this reader does not know (PLTE
      // cannot occur with these colour types): left to OpenCV.
      return std::nullopt;
    }
    at += 12 + std::size_t{length};
  }
  if (!header || compressed.empty()) return std::nullopt;

  const std::size_t row_bytes = std::size_t{width} * channels;
  std::vector<std::uint8_t> filtered((row_bytes + 1) * height);
  thread_local std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> decompressor(
      libdeflate_alloc_decompressor());
  if (!decompressor) return std::nullopt;
  // Exactly one filter byte and one row per line of the image; the zlib
  // checksum is verified.
  if (libdeflate_zlib_decompress(decompressor.get(), compressed.data(), compressed.size(),
                                 filtered.data(), filtered.size(), nullptr) != LIBDEFLATE_SUCCESS)
    return std::nullopt;

  cv::Mat image(static_cast<int>(height), static_cast<int>(width), CV_8UC(channels));
  const std::vector<std::uint8_t> zeros(row_bytes, 0);
  for (int y = 0; y < image.rows; ++y) {
    const std::uint8_t* line = &filtered[static_cast<std::size_t>(y) * (row_bytes + 1)];
    const std::uint8_t* prev = y > 0 ? image.ptr<std::uint8_t>(y - 1) : zeros.data();
    if (!Unfilter(line[0], line + 1, prev, image.ptr<std::uint8_t>(y), row_bytes,
                  static_cast<std::size_t>(channels)))
      return std::nullopt;
  }
  // PNG stores RGB(A); cv::imread without IMREAD_UNCHANGED gives BGR and
  // drops the alpha channel.
  if (channels == 3) cv::cvtColor(image, image, cv::COLOR_RGB2BGR);
  if (channels == 4) cv::cvtColor(image, image, cv::COLOR_RGBA2BGR);
  return image;
}

bool HaveFastPngReader() { return true; }

}  // namespace handeye::internal

#else  // without libdeflate every file goes to OpenCV

namespace handeye::internal {
std::optional<cv::Mat> ReadPng8(const std::string&) { return std::nullopt; }
bool HaveFastPngReader() { return false; }
}  // namespace handeye::internal

#endif
