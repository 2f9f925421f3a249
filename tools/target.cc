// SPDX-License-Identifier: GPL-2.0-or-later
// `handeye target [TYPE] [target options] -o FILE.png [--dpi D]`: draws a
// printable target (SPEC §7) from the target's own texture (Target::Albedo,
// the same one the renderer of `handeye simulate` samples) and writes its
// dataset `target` object next to it as FILE.json.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <vector>

#include "cli_numbers.h"
#include "commands.h"
#include "handeye/core/error.h"
#include "handeye/io/atomic_file.h"
#include "handeye/io/json_util.h"
#include "output_paths.h"
#include "target_options.h"

namespace handeye::tools {
namespace {

constexpr double kMetresPerInch = 0.0254;

struct TargetArgs {
  TargetOptions target;
  std::string output;
  double dpi = 300;
};

/// The printed face seen from the front at `dpi`: row 0 at the sheet's top
/// (smallest y), white 255, black 0. A pixel whose four quarter-pixel samples
/// agree takes their value; others (edges) average 8 × 8 samples.
cv::Mat DrawSheet(const Target& target, double dpi) {
  const Eigen::AlignedBox2d extent = target.Extent();
  const double pitch_m = kMetresPerInch / dpi;
  const int width = static_cast<int>(std::lround(extent.sizes().x() / pitch_m));
  const int height = static_cast<int>(std::lround(extent.sizes().y() / pitch_m));
  cv::Mat image(height, width, CV_8UC1);
  cv::parallel_for_(cv::Range(0, height), [&](const cv::Range& rows) {
    for (int r = rows.start; r < rows.end; ++r) {
      auto* out = image.ptr<std::uint8_t>(r);
      for (int c = 0; c < width; ++c) {
        auto albedo = [&](double fu, double fv) {  // fu, fv in [0, 1) across the pixel
          return target.Albedo(extent.min().x() + (c + fu) * pitch_m,
                               extent.min().y() + (r + fv) * pitch_m);
        };
        const double a = albedo(0.25, 0.25);
        double value = a;
        if (albedo(0.75, 0.25) != a || albedo(0.25, 0.75) != a || albedo(0.75, 0.75) != a) {
          double sum = 0;
          for (int i = 0; i < 8; ++i)
            for (int j = 0; j < 8; ++j) sum += albedo((i + 0.5) / 8, (j + 0.5) / 8);
          value = sum / 64;
        }
        out[c] = static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(value, 0.0, 1.0)));
      }
    }
  });
  return image;
}

std::uint32_t Crc32(const std::uint8_t* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  std::uint32_t crc = 0xffffffffu;
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xff] ^ (crc >> 8);
  return crc ^ 0xffffffffu;
}

void AppendBigEndian(std::uint32_t value, std::vector<std::uint8_t>* out) {
  for (int shift = 24; shift >= 0; shift -= 8)
    out->push_back(static_cast<std::uint8_t>(value >> shift));
}

/// PNG bytes with a pHYs chunk (pixels per metre) after the header, so that
/// printing at 100 % gives the target's true size. OpenCV writes none.
std::string PngWithResolution(const cv::Mat& image, double dpi) {
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", image, png)) throw std::runtime_error("cannot encode PNG");
  // Signature (8 bytes), then IHDR: length (4), type (4), 13 data bytes, CRC (4).
  const std::size_t after_ihdr = 8 + 4 + 4 + 13 + 4;
  if (png.size() < after_ihdr) throw std::runtime_error("unexpected PNG layout");
  const auto pixels_per_metre = static_cast<std::uint32_t>(std::lround(dpi / kMetresPerInch));
  std::vector<std::uint8_t> chunk;
  AppendBigEndian(9, &chunk);
  const std::size_t type_at = chunk.size();
  for (char ch : {'p', 'H', 'Y', 's'}) chunk.push_back(static_cast<std::uint8_t>(ch));
  AppendBigEndian(pixels_per_metre, &chunk);
  AppendBigEndian(pixels_per_metre, &chunk);
  chunk.push_back(1);  // unit: metre
  AppendBigEndian(Crc32(chunk.data() + type_at, chunk.size() - type_at), &chunk);
  png.insert(png.begin() + static_cast<std::ptrdiff_t>(after_ihdr), chunk.begin(), chunk.end());
  return std::string(png.begin(), png.end());
}

void RunTarget(const TargetArgs& args) {
  namespace fs = std::filesystem;
  if (!(std::isfinite(args.dpi) && args.dpi >= 10 && args.dpi <= 2400))
    throw InputError("", "--dpi", "expected a resolution between 10 and 2400 dots per inch");
  const fs::path out(args.output);
  if (out.extension() != ".png") throw InputError(args.output, "", "expected a .png file name");
  CheckFileOutputs({{"--target-json", args.target.target_json}},
                   {{"-o", args.output},
                    {"the .json beside -o", fs::path(out).replace_extension(".json").string()}});

  const auto target = MakeTargetFromOptions(args.target, false);
  PrintWarnings(target->Warnings());
  const cv::Mat sheet = DrawSheet(*target, args.dpi);
  const fs::path json = fs::path(out).replace_extension(".json");
  WriteFileAtomically(out.string(), PngWithResolution(sheet, args.dpi));
  WriteFileAtomically(json.string(), DumpJson(JsonFromTargetSpec(target->Spec())));

  const Eigen::Vector2d size_mm = 1000.0 * target->Extent().sizes();
  std::ostringstream line;
  line.setf(std::ios::fixed);
  line.precision(1);
  line << "wrote " << out.string() << " (" << target->Type() << ", " << size_mm.x() << " x "
       << size_mm.y() << " mm, " << sheet.cols << " x " << sheet.rows << " px at " << args.dpi
       << " dpi; print at 100 %) and " << json.string() << " (its dataset target object)\n";
  std::cout << line.str();
}

}  // namespace

void RegisterTarget(CLI::App& app) {
  auto args = std::make_shared<TargetArgs>();
  CLI::App* cmd = app.add_subcommand(
      "target", "draw a printable target (PNG at a given dpi) and write its dataset target object");
  cmd->add_option("TYPE", args->target.type,
                  "checkerboard (default), charuco or aprilgrid; each has a default sheet");
  cmd->add_option("-o,--output", args->output,
                  "PNG to write; FILE.json beside it gets the dataset `target` object")
      ->required();
  cmd->add_option("--dpi", args->dpi, "dots per inch (default 300)")
      ->check(NumberIn(10, 2400, false, "a resolution between 10 and 2400 dots per inch"));
  AddTargetOptions(cmd, &args->target);
  cmd->callback([args]() { RunTarget(*args); });
}

HANDEYE_SUBCOMMAND(70, RegisterTarget);

}  // namespace handeye::tools
