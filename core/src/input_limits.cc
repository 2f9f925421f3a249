// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/input_limits.h"

#include <cmath>
#include <cstdlib>

#include "handeye/core/error.h"

namespace handeye {
namespace {

constexpr char kTargetPointsVariable[] = "HANDEYE_MAX_TARGET_POINTS";
constexpr char kImagePixelsVariable[] = "HANDEYE_MAX_IMAGE_PIXELS";

// Read at each check rather than once, so that a test or a program that
// embeds the library can change it; a check happens once per target or image.
std::int64_t LimitFromEnvironment(const char* variable, std::int64_t fallback) {
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

}  // namespace

std::int64_t MaxTargetPoints() {
  return LimitFromEnvironment(kTargetPointsVariable, kDefaultMaxTargetPoints);
}

std::int64_t MaxImagePixels() {
  return LimitFromEnvironment(kImagePixelsVariable, kDefaultMaxImagePixels);
}

void RequireTargetPointsWithinLimit(std::int64_t cols, std::int64_t rows,
                                    const std::string& json_path) {
  const std::int64_t cap = MaxTargetPoints();
  if (cols * rows > cap)
    throw InputError("", json_path,
                     std::to_string(cols) + " x " + std::to_string(rows) + " = " +
                         std::to_string(cols * rows) + " target points; expected at most " +
                         std::to_string(cap) + " (set " + kTargetPointsVariable +
                         " to allow a larger board)");
}

void RequireImagePixelsWithinLimit(std::int64_t width, std::int64_t height, const std::string& file,
                                   const std::string& json_path) {
  const std::int64_t cap = MaxImagePixels();
  if (width * height > cap)
    throw InputError(file, json_path,
                     std::to_string(width) + " x " + std::to_string(height) + " = " +
                         std::to_string(width * height) + " pixels; expected at most " +
                         std::to_string(cap) + " per image (set " + kImagePixelsVariable +
                         " to allow larger images)");
}

}  // namespace handeye
