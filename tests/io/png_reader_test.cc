// SPDX-License-Identifier: GPL-2.0-or-later
// The PNG reader (libspng) against libpng (through cv::imread): PNG files
// written here byte by byte with every row filter, files OpenCV writes in
// every depth and colour type, damaged files and headers that lie.
#include "../../io/src/png_reader.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
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

using Catch::Matchers::Contains;
using Bytes = std::vector<std::uint8_t>;

void Append32(Bytes* out, std::uint32_t v) {
  for (int shift : {24, 16, 8, 0}) out->push_back(static_cast<std::uint8_t>(v >> shift));
}

void AppendChunk(Bytes* png, const char* type, const Bytes& data) {
  Append32(png, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = png->size();
  png->insert(png->end(), type, type + 4);
  png->insert(png->end(), data.begin(), data.end());
  Append32(png, test::Crc32(png->data() + start, png->size() - start));
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
Bytes EncodePng(int width, int height, int channels, const Bytes& pixels, int interlace = 0,
               std::uint32_t header_width = 0, std::uint32_t header_height = 0) {
  const int colour = channels == 1 ? 0 : channels == 3 ? 2 : 6;
  Bytes png = {137, 80, 78, 71, 13, 10, 26, 10};
  Bytes header;
  // A header may claim another size than the pixels that follow.
  Append32(&header, header_width ? header_width : static_cast<std::uint32_t>(width));
  Append32(&header, header_height ? header_height : static_cast<std::uint32_t>(height));
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

/// What LoadGrayImage must give: cv::imread, then grey and 8 bits.
cv::Mat ImreadGrey(const std::string& path) {
  cv::Mat image = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  REQUIRE(!image.empty());
  if (image.channels() == 3) cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
  if (image.channels() == 4) cv::cvtColor(image, image, cv::COLOR_BGRA2GRAY);
  if (image.depth() == CV_16U) image.convertTo(image, CV_8U, 1.0 / 257.0);
  return image;
}

Bytes ReadBytes(const std::string& path) {
  const std::string text = test::ReadText(path);
  return Bytes(text.begin(), text.end());
}

cv::Mat Decode(const Bytes& png, const std::string& name = "mem.png") {
  return internal::DecodePngGray(png.data(), png.size(), name, [](std::uint32_t, std::uint32_t) {});
}

/// The message of the InputError that loading `path` throws ("" if none).
std::string LoadError(const std::string& path, const Camera& camera) {
  try {
    LoadGrayImage(path, camera);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("PNG reader decodes every row filter as libpng does", "[png]") {
  const std::string dir = test::TempDir("png_reader_filters");
  for (const int channels : {1, 3, 4}) {
    // Odd sizes; more than 64 KiB of data for the grey one, so the stored
    // stream has several blocks.
    const int width = channels == 1 ? 301 : 37, height = channels == 1 ? 233 : 23;
    const std::string path = dir + "/c" + std::to_string(channels) + ".png";
    WriteBytes(path, EncodePng(width, height, channels,
                               RandomPixels(static_cast<std::size_t>(width) * height * channels,
                                            static_cast<std::uint32_t>(channels))));
    INFO(channels << " channels");
    CHECK(SameImage(Decode(ReadBytes(path)), ImreadGrey(path)));
  }
}

TEST_CASE("PNG reader decodes OpenCV's PNGs of every depth and colour type", "[png]") {
  const std::string dir = test::TempDir("png_reader_opencv");
  cv::Mat grey(480, 640, CV_8UC1), colour(120, 160, CV_8UC3), alpha(50, 70, CV_8UC4);
  cv::Mat deep_grey(23, 37, CV_16UC1), deep_colour(23, 37, CV_16UC3);
  cv::randu(grey, 0, 40);  // low entropy: real deflate codes, not stored blocks
  grey(cv::Rect(100, 100, 200, 150)).setTo(200);
  cv::randu(colour, 0, 255);
  cv::randu(alpha, 0, 255);
  cv::randu(deep_grey, 0, 65535);
  cv::randu(deep_colour, 0, 65535);
  for (const auto& [name, image] : {std::pair{"grey", grey}, std::pair{"colour", colour}, std::pair{"alpha", alpha},
                                    std::pair{"deep_grey", deep_grey}, std::pair{"deep_colour", deep_colour}}) {
    const std::string path = dir + "/" + name + ".png";
    REQUIRE(cv::imwrite(path, image));
    INFO(name);
    const cv::Mat decoded = Decode(ReadBytes(path));
    CHECK(decoded.type() == CV_8UC1);
    CHECK(SameImage(decoded, ImreadGrey(path)));
  }
  // 8-bit grey comes back as written.
  CHECK(SameImage(Decode(ReadBytes(dir + "/grey.png")), grey));
}

TEST_CASE("PNG reader: damaged files are InputErrors, not libpng messages", "[png][bad]") {
  const Bytes png = EncodePng(37, 23, 1, RandomPixels(37 * 23, 5));
  REQUIRE(Decode(png).size() == cv::Size(37, 23));
  auto error_of = [](const Bytes& bytes) -> std::string {
    try {
      Decode(bytes, "bad.png");
    } catch (const InputError& e) {
      CHECK(e.file() == "bad.png");
      return e.what();
    }
    return "";
  };
  // A cut file: the image data ends early.
  CHECK_THAT(error_of(Bytes(png.begin(), png.begin() + static_cast<std::ptrdiff_t>(png.size() * 3 / 4))),
             Contains("bad.png: damaged PNG: the file ends too early (truncated); expected a complete PNG file"));
  // A flipped byte fails the chunk's CRC.
  Bytes flipped = png;
  flipped[png.size() / 2] ^= 0x10;
  CHECK_THAT(error_of(flipped), Contains("bad.png: damaged PNG: "));
  // Only the signature, and a header alone.
  CHECK_THAT(error_of(Bytes(png.begin(), png.begin() + 8)), Contains("damaged PNG"));
  CHECK_THAT(error_of(Bytes(png.begin(), png.begin() + 33)), Contains("damaged PNG"));
}

TEST_CASE("PNG header sizes are checked before any pixel memory is allocated", "[png][bad]") {
  const std::string dir = test::TempDir("png_reader_huge");
  const Camera camera = SmallCamera();
  // Headers that claim 100000 x 100000 (10^10 pixels) and 65536 x 65536
  // followed by a few bytes of data: refused from the header, naming the
  // file and the size, without trying to allocate gigabytes.
  for (const std::uint32_t side : {100000u, 65536u}) {
    const std::string path = dir + "/huge" + std::to_string(side) + ".png";
    WriteBytes(path, EncodePng(37, 23, 3, RandomPixels(37 * 23 * 3, 9), 0, side, side));
    const std::string size = std::to_string(side) + "x" + std::to_string(side);
    CHECK_THAT(LoadError(path, camera),
               Contains(path + ": image is " + size + " but camera 'cam' has image_size [37, 23]"));
    // The decoder shows the header's size to its caller before decoding.
    const Bytes bytes = ReadBytes(path);
    std::uint64_t seen = 0;
    CHECK_THROWS_AS(internal::DecodePngGray(bytes.data(), bytes.size(), path,
                                            [&](std::uint32_t w, std::uint32_t h) {
                                              seen = std::uint64_t{w} * h;
                                              throw InputError(path, "", "too big");
                                            }),
                    InputError);
    CHECK(seen == std::uint64_t{side} * side);
  }
}

TEST_CASE("LoadGrayImage reads PNG with libspng and the rest with OpenCV", "[png]") {
  const std::string dir = test::TempDir("png_reader_grey");
  const Camera camera = SmallCamera();
  for (const int channels : {1, 3, 4}) {
    const std::string path = dir + "/c" + std::to_string(channels) + ".png";
    WriteBytes(path, EncodePng(37, 23, channels,
                               RandomPixels(37 * 23 * static_cast<std::size_t>(channels),
                                            static_cast<std::uint32_t>(10 + channels))));
    INFO(channels << " channels");
    CHECK(SameImage(LoadGrayImage(path, camera), ImreadGrey(path)));
  }
  // A PNG named .jpg is still a PNG (the signature decides), a TIFF is OpenCV's.
  cv::Mat grey(23, 37, CV_8UC1);
  cv::randu(grey, 0, 255);
  REQUIRE(cv::imwrite(dir + "/real.png", grey));
  std::filesystem::copy_file(dir + "/real.png", dir + "/named.jpg");
  CHECK(SameImage(LoadGrayImage(dir + "/named.jpg", camera), grey));
  REQUIRE(cv::imwrite(dir + "/real.tiff", grey));
  CHECK(SameImage(LoadGrayImage(dir + "/real.tiff", camera), grey));

  // A cut PNG, text named .png, a missing file, a folder.
  const Bytes png = EncodePng(37, 23, 1, RandomPixels(37 * 23, 5));
  WriteBytes(dir + "/cut.png", Bytes(png.begin(), png.begin() + static_cast<std::ptrdiff_t>(png.size() / 2)));
  CHECK_THAT(LoadError(dir + "/cut.png", camera), Contains(dir + "/cut.png: damaged PNG: the file ends too early"));
  test::WriteText(dir + "/text.png", "not an image");
  CHECK_THAT(LoadError(dir + "/text.png", camera),
             Contains(dir + "/text.png: unreadable image: expected a PNG, JPEG or TIFF file"));
  CHECK_THAT(LoadError(dir + "/missing.png", camera), Contains("image file does not exist (camera 'cam')"));
  // A wrong size from the file's own header, for PNG and for OpenCV's formats.
  Camera other = camera;
  other.width = 40;
  CHECK_THAT(LoadError(dir + "/real.png", other), Contains("image is 37x23 but camera 'cam' has image_size [40, 23]"));
  CHECK_THAT(LoadError(dir + "/real.tiff", other), Contains("image is 37x23 but camera 'cam' has image_size [40, 23]"));
}

TEST_CASE("An image larger than HANDEYE_MAX_IMAGE_PIXELS is refused before it is read", "[png][bad][limits]") {
  unsetenv("HANDEYE_MAX_IMAGE_PIXELS");
  const std::string dir = test::TempDir("png_reader_cap");
  // A camera that declares 65536 x 65536 and a PNG whose header says the
  // same: before, the decoder set aside 4 GB for it (9.5 GB through detect).
  Camera huge = SmallCamera();
  huge.width = huge.height = 65536;
  const std::string path = dir + "/huge.png";
  WriteBytes(path, EncodePng(37, 23, 1, RandomPixels(37 * 23, 4), 0, 65536, 65536));
  CHECK_THAT(LoadError(path, huge), Contains(path + ": 65536 x 65536 = 4294967296 pixels; expected at most "
                                                    "200000000 per image (raise it with --max-image-pixels or HANDEYE_MAX_IMAGE_PIXELS"));
}

}  // namespace handeye
