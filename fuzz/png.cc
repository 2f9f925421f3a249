// SPDX-License-Identifier: GPL-2.0-or-later
// The PNG reader (libspng) behind LoadGrayImage, on bytes in memory. The
// size check stands for the camera's image_size: anything larger than
// 2048 x 2048 is refused from the header, as a camera of that size would.
#include "../io/src/png_reader.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  handeye::fuzz::ExpectInputErrorsOnly([&] {
    handeye::internal::DecodePngGray(data, size, "fuzz.png", [](std::uint32_t width, std::uint32_t height) {
      if (width > 2048 || height > 2048) throw handeye::InputError("fuzz.png", "", "larger than the camera");
    });
  });
  return 0;
}
