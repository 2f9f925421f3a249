// SPDX-License-Identifier: GPL-2.0-or-later
// The libdeflate PNG reader against libpng (through cv::imread): PNG files
// written here byte by byte with every row filter, and files OpenCV writes.
#include "../../io/src/png_reader.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>
#include <vector>

#include "handeye/core/error.h"
#include "handeye/io/image.h"
#include "support/test_support.h"

namespace handeye {
namespace {

using Bytes = std::vector<std::uint8_t>;

void Append32(Bytes* out, std::uint32_t v) {
  for (int shift : {24, 16, 8, 0}) out->push_back(static_cast<std::uint8_t>(v >> shift));
}

std::uint32_t Crc32(const std::uint8_t* data, std::size_t n) {
  std::uint32_t crc = 0xffffffffu;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xffffffffu;
}

void AppendChunk(Bytes* png, const char* type, const Bytes& data) {
  Append32(png, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = png->size();
  png->insert(png->end(), type, type + 4);
  png->insert(png->end(), data.begin(), data.end());
  Append32(png, Crc32(png->data() + start, png->size() - start));
}

/// A zlib stream of stored (uncompressed) deflate blocks.
Bytes StoredZlib(const Bytes& raw) {
  Bytes z = {0x78, 0x01};
  std::size_t at = 0;
  do {
    const std::size_t n = std::min<std::size_t>(raw.size() - at, 65535);
    z.push_back(at + n == raw.size() ? 1 : 0);  // BFINAL, BTYPE 00
    z.push_back(static_cast<std::uint8_t>(n));
    z.push_back(static_cast<std::uint8_t>(n >> 8));
    z.push_back(static_cast<std::uint8_t>(~n));
    z.push_back(static_cast<std::uint8_t>(~n >> 8));
    z.insert(z.end(), raw.begin() + at, raw.begin() + at + n);
    at += n;
  } while (at < raw.size());
  std::uint32_t a = 1, b = 0;
  for (const std::uint8_t byte : raw) {
    a = (a + byte) % 65521;
    b = (b + a) % 65521;
  }
  Append32(&z, (b << 16) | a);
  return z;
}

int PaethPredictor(int left, int up, int upper_left) {
  const int p = left + up - upper_left;
  const int pa = std::abs(p - left), pb = std::abs(p - up), pc = std::abs(p - upper_left);
  if (pa <= pb && pa <= pc) return left;
  return pb <= pc ? up : upper_left;
}

/// PNG bytes of `pixels` (rows of width × channels bytes, RGB(A) order),
/// row y filtered with type y % 5, so every filter occurs.
Bytes EncodePng(int width, int height, int channels, const Bytes& pixels, int interlace = 0) {
  const int colour = channels == 1 ? 0 : channels == 3 ? 2 : 6;
  Bytes png = {137, 80, 78, 71, 13, 10, 26, 10};
  Bytes header;
  Append32(&header, static_cast<std::uint32_t>(width));
  Append32(&header, static_cast<std::uint32_t>(height));
  header.insert(header.end(), {8, static_cast<std::uint8_t>(colour), 0, 0,
                               static_cast<std::uint8_t>(interlace)});
  AppendChunk(&png, "IHDR", header);
  const int row_bytes = width * channels;
  auto at = [&](int x, int y) { return x < 0 || y < 0 ? 0 : int{pixels[y * row_bytes + x]}; };
  Bytes filtered;
  for (int y = 0; y < height; ++y) {
    const int type = y % 5;
    filtered.push_back(static_cast<std::uint8_t>(type));
    for (int x = 0; x < row_bytes; ++x) {
      const int left = at(x - channels, y), up = at(x, y - 1), upper_left = at(x - channels, y - 1);
      const int predicted = type == 0   ? 0
                            : type == 1 ? left
                            : type == 2 ? up
                            : type == 3 ? (left + up) / 2
                                        : PaethPredictor(left, up, upper_left);
      filtered.push_back(static_cast<std::uint8_t>(at(x, y) - predicted));
    }
  }
  // Two IDAT chunks: the reader must join them.
  const Bytes z = StoredZlib(filtered);
  AppendChunk(&png, "IDAT", Bytes(z.begin(), z.begin() + z.size() / 2));
  AppendChunk(&png, "IDAT", Bytes(z.begin() + z.size() / 2, z.end()));
  AppendChunk(&png, "IEND", {});
  return png;
}

void WriteBytes(const std::string& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  REQUIRE(out.good());
}

Bytes RandomPixels(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  Bytes pixels(n);
  for (auto& p : pixels) p = static_cast<std::uint8_t>(rng() & 0xff);
  return pixels;
}

/// The camera of the 37 x 23 images below (LoadGrayImage checks the size).
Camera SmallCamera() {
  Camera camera;
  camera.name = "cam";
  camera.width = 37;
  camera.height = 23;
  return camera;
}

bool SameImage(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

}  // namespace

TEST_CASE("PNG reader decodes every row filter as libpng does", "[png]") {
  if (!internal::HaveFastPngReader()) {
    WARN("built without libdeflate: every PNG goes to OpenCV, nothing to compare");
    return;
  }
  const std::string dir = test::TempDir("png_reader_filters");
  for (const int channels : {1, 3, 4}) {
    // Odd sizes; more than 64 KiB of data for the grey one, so the stored
    // stream has several blocks.
    const int width = channels == 1 ? 301 : 37, height = channels == 1 ? 233 : 23;
    const std::string path = dir + "/c" + std::to_string(channels) + ".png";
    WriteBytes(path, EncodePng(width, height, channels,
                               RandomPixels(static_cast<std::size_t>(width) * height * channels,
                                            static_cast<std::uint32_t>(channels))));
    const cv::Mat expected = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
    REQUIRE(!expected.empty());
    const std::optional<cv::Mat> decoded = internal::ReadPng8(path);
    INFO(channels << " channels");
    REQUIRE(decoded);
    CHECK(SameImage(*decoded, expected));
  }
}

TEST_CASE("PNG reader decodes OpenCV's own compressed PNGs", "[png]") {
  if (!internal::HaveFastPngReader()) {
    WARN("built without libdeflate: every PNG goes to OpenCV, nothing to compare");
    return;
  }
  const std::string dir = test::TempDir("png_reader_opencv");
  cv::Mat grey(480, 640, CV_8UC1), colour(120, 160, CV_8UC3);
  cv::randu(grey, 0, 40);  // low entropy: real deflate codes, not stored blocks
  grey(cv::Rect(100, 100, 200, 150)).setTo(200);
  cv::randu(colour, 0, 255);
  for (const auto& [name, image] : {std::pair{"grey", grey}, std::pair{"colour", colour}}) {
    const std::string path = dir + "/" + name + ".png";
    REQUIRE(cv::imwrite(path, image));
    const std::optional<cv::Mat> decoded = internal::ReadPng8(path);
    INFO(name);
    REQUIRE(decoded);
    CHECK(SameImage(*decoded, cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR)));
    CHECK(SameImage(*decoded, image));
  }
}

TEST_CASE("PNG reader leaves what it does not handle to OpenCV", "[png]") {
  const std::string dir = test::TempDir("png_reader_fallback");
  const Camera camera = SmallCamera();
  const Bytes pixels = RandomPixels(37 * 23, 5);

  // 16-bit: OpenCV reads it, LoadGrayImage scales it to 8 bits.
  cv::Mat deep(23, 37, CV_16UC1);
  cv::randu(deep, 0, 65535);
  REQUIRE(cv::imwrite(dir + "/deep.png", deep));
  CHECK_FALSE(internal::ReadPng8(dir + "/deep.png"));
  const cv::Mat loaded = LoadGrayImage(dir + "/deep.png", camera);
  CHECK(loaded.type() == CV_8UC1);
  cv::Mat scaled;
  deep.convertTo(scaled, CV_8U, 1.0 / 257.0);
  CHECK(SameImage(loaded, scaled));

  // Interlaced (Adam7) is not decoded here.
  WriteBytes(dir + "/interlaced.png", EncodePng(37, 23, 1, pixels, 1));
  CHECK_FALSE(internal::ReadPng8(dir + "/interlaced.png"));

  // Damaged data: a flipped byte fails the chunk CRC (and the zlib checksum);
  // a cut file has no IEND. Neither decodes, and loading says so.
  Bytes png = EncodePng(37, 23, 1, pixels);
  const std::string good = dir + "/good.png", flipped = dir + "/flipped.png", cut = dir + "/cut.png";
  WriteBytes(good, png);
  if (internal::HaveFastPngReader()) REQUIRE(internal::ReadPng8(good));
  Bytes damaged = png;
  damaged[png.size() / 2] ^= 0x10;
  WriteBytes(flipped, damaged);
  CHECK_FALSE(internal::ReadPng8(flipped));
  WriteBytes(cut, Bytes(png.begin(), png.begin() + static_cast<std::ptrdiff_t>(png.size() * 3 / 4)));
  CHECK_FALSE(internal::ReadPng8(cut));
  CHECK_THROWS_AS(LoadGrayImage(cut, camera), InputError);

  // Not a PNG at all, and a missing file.
  test::WriteText(dir + "/text.png", "not an image");
  CHECK_FALSE(internal::ReadPng8(dir + "/text.png"));
  CHECK_THROWS_AS(LoadGrayImage(dir + "/text.png", camera), InputError);
  CHECK_FALSE(internal::ReadPng8(dir + "/missing.png"));
}

TEST_CASE("LoadGrayImage gives the same grey through either reader", "[png]") {
  const std::string dir = test::TempDir("png_reader_grey");
  const Camera camera = SmallCamera();
  for (const int channels : {1, 3, 4}) {
    const std::string path = dir + "/c" + std::to_string(channels) + ".png";
    WriteBytes(path, EncodePng(37, 23, channels,
                               RandomPixels(37 * 23 * static_cast<std::size_t>(channels),
                                            static_cast<std::uint32_t>(10 + channels))));
    cv::Mat expected = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
    if (channels == 3) cv::cvtColor(expected, expected, cv::COLOR_BGR2GRAY);
    if (channels == 4) cv::cvtColor(expected, expected, cv::COLOR_BGRA2GRAY);
    INFO(channels << " channels");
    CHECK(SameImage(LoadGrayImage(path, camera), expected));
  }
}

}  // namespace handeye
