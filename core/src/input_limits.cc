// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/input_limits.h"

#include <atomic>
#include <cmath>
#include <cstdlib>

#include "handeye/core/error.h"

namespace handeye {
namespace {

constexpr char kTargetPointsVariable[] = "HANDEYE_MAX_TARGET_POINTS";
constexpr char kImagePixelsVariable[] = "HANDEYE_MAX_IMAGE_PIXELS";

// Set by SetMaxTargetPoints / SetMaxImagePixels (the command line's
// --max-target-points, --max-image-pixels); 0 while unset.
std::atomic<std::int64_t> target_points_set{0};
std::atomic<std::int64_t> image_pixels_set{0};

// Read at each check rather than once, so that a test or a program that
// embeds the library can change it; a check happens once per target or image.
std::int64_t Limit(const std::atomic<std::int64_t>& set, const char* variable, std::int64_t fallback) {
  if (const std::int64_t value = set.load(); value > 0) return value;
  const char* text = std::getenv(variable);
  if (text == nullptr || *text == '\0') return fallback;
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  // Up to 2^53, where every integer is a double.
  if (*end != '\0' || !(value >= 1) || value > 9007199254740992.0 || value != std::floor(value))
    throw InputError("", "",
                     std::string("environment variable ") + variable +
                         ": expected a positive integer, got '" + text + "'");
  return static_cast<std::int64_t>(value);
}

void RequirePositiveLimit(std::int64_t value, const char* what) {
  if (value < 1)
    throw InputError("", "", std::string(what) + ": expected a positive integer, got " + std::to_string(value));
}

}  // namespace

std::int64_t MaxTargetPoints() {
  return Limit(target_points_set, kTargetPointsVariable, kDefaultMaxTargetPoints);
}

std::int64_t MaxImagePixels() {
  return Limit(image_pixels_set, kImagePixelsVariable, kDefaultMaxImagePixels);
}

void SetMaxTargetPoints(std::int64_t points) {
  RequirePositiveLimit(points, "--max-target-points");
  target_points_set = points;
}

void SetMaxImagePixels(std::int64_t pixels) {
  RequirePositiveLimit(pixels, "--max-image-pixels");
  image_pixels_set = pixels;
}

void RequireTargetPointsWithinLimit(std::int64_t cols, std::int64_t rows,
                                    const std::string& json_path) {
  const std::int64_t cap = MaxTargetPoints();
  if (cols * rows > cap)
    throw InputError("", json_path,
                     std::to_string(cols) + " x " + std::to_string(rows) + " = " +
                         std::to_string(cols * rows) + " target points; expected at most " +
                         std::to_string(cap) + " (raise it with --max-target-points or " + kTargetPointsVariable +
                         " to allow a larger board)");
}

void RequireImagePixelsWithinLimit(std::int64_t width, std::int64_t height, const std::string& file,
                                   const std::string& json_path) {
  const std::int64_t cap = MaxImagePixels();
  if (width * height > cap)
    throw InputError(file, json_path,
                     std::to_string(width) + " x " + std::to_string(height) + " = " +
                         std::to_string(width * height) + " pixels; expected at most " +
                         std::to_string(cap) + " per image (raise it with --max-image-pixels or " + kImagePixelsVariable +
                         " to allow larger images)");
}

}  // namespace handeye
