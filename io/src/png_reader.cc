// SPDX-License-Identifier: GPL-2.0-or-later
#include "png_reader.h"

#include <libdeflate.h>
#include <spng.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>
#include <vector>

#include "handeye/core/error.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

// Why libspng, and libdeflate beside it (issues 15 and 12): libspng reads
// every PNG form and names what is wrong with a damaged file, so every file
// goes through it first. It inflates with zlib, which was slow on the
// cameras' images that compress well: on METRIC's medium cell as published
// (1920x1080 RGB, 70 KB a file) libspng took 27 ms of CPU per image, 40 % of
// a whole `handeye calibrate` (perf: zlib 22 %, libspng's row decoding 13 %),
// where libdeflate inflates the same stream in 1.4 ms. So the common files --
// 8-bit grey, RGB or RGBA, not interlaced, intact -- are inflated with
// libdeflate and unfiltered here (DecodeCommonPng, a few dozen lines); any
// other file, and any file this path finds damaged, is decoded by libspng,
// which gives the error. Both give the same pixels (tests/io/
// png_reader_test.cc compares every row filter and colour type with libpng).

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

std::uint32_t BigEndian32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

/// PNG's Paeth predictor (PNG §9.4): of left, up and upper left, the one
/// nearest to left + up - upper left.
inline int Paeth(int left, int up, int upper_left) {
  const int p = left + up - upper_left;
  const int pa = std::abs(p - left), pb = std::abs(p - up), pc = std::abs(p - upper_left);
  if (pa <= pb && pa <= pc) return left;
  return pb <= pc ? up : upper_left;
}

/// Undoes the Sub filter (each byte plus the one a pixel to its left) for
/// pixels of kBpp bytes, the left pixel kept in registers: a loop reading
/// back the byte it wrote three bytes before ran at a third of the speed,
/// and cameras' PNGs are often filtered with Sub on every row (METRIC's are).
/// `left` is the pixel before raw[0] (zeros at a row's start).
template <int kBpp>
void UnfilterSubScalar(const std::uint8_t* raw, std::uint8_t* out, std::size_t row_bytes,
                       std::array<std::uint8_t, kBpp> left) {
  for (std::size_t i = 0; i + kBpp <= row_bytes; i += kBpp) {
    for (int c = 0; c < kBpp; ++c)
      out[i + c] = left[c] = static_cast<std::uint8_t>(left[c] + raw[i + c]);
  }
}

template <int kBpp>
void UnfilterSub(const std::uint8_t* raw, std::uint8_t* out, std::size_t row_bytes) {
  std::size_t i = 0;
  std::array<std::uint8_t, kBpp> left{};
#if defined(__SSE2__)
  // Sub is a running sum per channel, 16 bytes at a time: the whole pixels
  // of a register (5 of 3 bytes, 4 of 4, 16 of 1) summed within it by adding
  // it shifted by 1, 2, 4 and 8 pixels, then the running sum of the blocks
  // before added to every pixel. That sum grows by the block's last pixel,
  // spread over every pixel the same way: the one add that waits on the
  // block before. On METRIC's images (Sub on every row) the scalar loop was
  // 18 % of a `handeye calibrate`.
  constexpr int kStep = 16 / kBpp * kBpp;  // bytes of whole pixels in a register
  const auto sum_pixels = [](__m128i x) {
    x = _mm_add_epi8(x, _mm_slli_si128(x, kBpp));
    x = _mm_add_epi8(x, _mm_slli_si128(x, 2 * kBpp));
    if constexpr (4 * kBpp < 16) x = _mm_add_epi8(x, _mm_slli_si128(x, 4 * kBpp));
    if constexpr (8 * kBpp < 16) x = _mm_add_epi8(x, _mm_slli_si128(x, 8 * kBpp));
    return x;
  };
  __m128i before = _mm_setzero_si128();  // the running sum, in every pixel
  for (; i + 16 <= row_bytes; i += kStep) {
    const __m128i block = sum_pixels(_mm_loadu_si128(reinterpret_cast<const __m128i*>(raw + i)));
    // 16 bytes stored: past kStep (one byte for 3-byte pixels) the next block overwrites them.
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), _mm_add_epi8(block, before));
    before = _mm_add_epi8(before,
                          sum_pixels(_mm_srli_si128(_mm_slli_si128(block, 16 - kStep), 16 - kBpp)));
  }
  if (i > 0) std::memcpy(left.data(), out + i - kBpp, kBpp);
#endif
  UnfilterSubScalar<kBpp>(raw + i, out + i, row_bytes - i, left);
}

/// Undoes one row's filter: `raw` (row_bytes) into `out`, with `up` the row
/// above, already unfiltered (zeros above the first row), `bpp` bytes a
/// pixel. False for a filter type PNG does not have.
bool Unfilter(int type, const std::uint8_t* raw, const std::uint8_t* up, std::uint8_t* out,
              std::size_t row_bytes, std::size_t bpp) {
  switch (type) {
    case 0:
      std::memcpy(out, raw, row_bytes);
      return true;
    case 1:
      if (bpp == 1) UnfilterSub<1>(raw, out, row_bytes);
      if (bpp == 3) UnfilterSub<3>(raw, out, row_bytes);
      if (bpp == 4) UnfilterSub<4>(raw, out, row_bytes);
      return true;
    case 2:
      for (std::size_t i = 0; i < row_bytes; ++i)
        out[i] = static_cast<std::uint8_t>(raw[i] + up[i]);
      return true;
    case 3:
      for (std::size_t i = 0; i < row_bytes; ++i) {
        const int left = i >= bpp ? out[i - bpp] : 0;
        out[i] = static_cast<std::uint8_t>(raw[i] + ((left + up[i]) >> 1));
      }
      return true;
    case 4:
      for (std::size_t i = 0; i < row_bytes; ++i) {
        const int left = i >= bpp ? out[i - bpp] : 0, upper_left = i >= bpp ? up[i - bpp] : 0;
        out[i] = static_cast<std::uint8_t>(raw[i] + Paeth(left, up[i], upper_left));
      }
      return true;
    default:
      return false;
  }
}

struct DecompressorDeleter {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

/// The grey image of a PNG whose header (checked by libspng) says 8-bit grey,
/// RGB or RGBA without interlacing, inflated by libdeflate; nullopt when the
/// file has another critical chunk or anything is damaged (a chunk's CRC,
/// the zlib stream, its length, a filter type), so that libspng decodes it
/// and says what is wrong.
std::optional<cv::Mat> DecodeCommonPng(const std::uint8_t* data, std::size_t size,
                                       const spng_ihdr& header) {
  int channels = 0, to_grey = -1;
  if (header.bit_depth != 8 || header.interlace_method != 0) return std::nullopt;
  if (header.color_type == SPNG_COLOR_TYPE_GRAYSCALE) {
    channels = 1;
  } else if (header.color_type == SPNG_COLOR_TYPE_TRUECOLOR) {
    channels = 3;
    to_grey = cv::COLOR_RGB2GRAY;
  } else if (header.color_type == SPNG_COLOR_TYPE_TRUECOLOR_ALPHA) {
    channels = 4;
    to_grey = cv::COLOR_RGBA2GRAY;
  } else {
    return std::nullopt;
  }
  // The chunks after the signature: IDAT ones, in one run, joined; IHDR,
  // IEND and ancillary chunks (which libspng's decoding to RGB ignores too)
  // skipped, a suggested palette (PLTE) as well.
  std::vector<std::uint8_t> stream;
  bool idat_run_over = false, end = false;
  for (std::size_t at = 8; !end;) {
    if (size - at < 12) return std::nullopt;
    const std::uint32_t length = BigEndian32(data + at);
    if (length > size - at - 12) return std::nullopt;
    const std::uint8_t* type = data + at + 4;
    const bool idat = std::memcmp(type, "IDAT", 4) == 0;
    end = std::memcmp(type, "IEND", 4) == 0;
    const bool critical = (type[0] & 0x20) == 0;
    if (idat) {
      if (idat_run_over || libdeflate_crc32(0, type, length + 4) != BigEndian32(type + 4 + length))
        return std::nullopt;
      stream.insert(stream.end(), type + 4, type + 4 + length);
    } else {
      if (!stream.empty()) idat_run_over = true;
      if (critical && !end && std::memcmp(type, "IHDR", 4) != 0 &&
          std::memcmp(type, "PLTE", 4) != 0)
        return std::nullopt;
    }
    at += 12 + std::size_t{length};
  }
  const std::size_t row_bytes = std::size_t{header.width} * channels;
  // One filter byte before every row; the stream must fill exactly that.
  const std::size_t filtered_size = (row_bytes + 1) * header.height;
  const std::unique_ptr<std::uint8_t[]> filtered(new std::uint8_t[filtered_size]);
  std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> inflater(
      libdeflate_alloc_decompressor());
  if (!inflater) throw std::bad_alloc();
  if (libdeflate_zlib_decompress(inflater.get(), stream.data(), stream.size(), filtered.get(),
                                 filtered_size, nullptr) != LIBDEFLATE_SUCCESS)
    return std::nullopt;

  cv::Mat grey(static_cast<int>(header.height), static_cast<int>(header.width), CV_8UC1);
  if (channels == 1) {
    const std::vector<std::uint8_t> zeros(row_bytes, 0);
    for (int y = 0; y < grey.rows; ++y) {
      const std::uint8_t* line = &filtered[y * (row_bytes + 1)];
      if (!Unfilter(line[0], line + 1, y > 0 ? grey.ptr(y - 1) : zeros.data(), grey.ptr(y),
                    row_bytes, 1))
        return std::nullopt;
    }
    return grey;
  }
  // Colour rows unfiltered a block at a time and turned grey by OpenCV (the
  // same weights as the other paths), so the colour image is never whole.
  constexpr int kBlockRows = 64;
  cv::Mat block(kBlockRows + 1, static_cast<int>(header.width), CV_8UC(channels),
                cv::Scalar::all(0));
  for (int y0 = 0; y0 < grey.rows; y0 += kBlockRows) {
    const int rows = std::min(kBlockRows, grey.rows - y0);
    // Row 0 of the block holds the row above it (zeros above the image).
    if (y0 > 0) block.row(kBlockRows).copyTo(block.row(0));
    for (int r = 1; r <= rows; ++r) {
      const std::uint8_t* line = &filtered[(y0 + r - 1) * (row_bytes + 1)];
      if (!Unfilter(line[0], line + 1, block.ptr(r - 1), block.ptr(r), row_bytes, channels))
        return std::nullopt;
    }
    cv::Mat grey_rows = grey.rowRange(y0, y0 + rows);
    cv::cvtColor(block.rowRange(1, rows + 1), grey_rows, to_grey);
  }
  return grey;
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
  if (std::optional<cv::Mat> common = DecodeCommonPng(data, size, header))
    return *std::move(common);

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
