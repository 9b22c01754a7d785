// libFuzzer target: arbitrary bytes as the contents of an image file, through decode_image, the
// function `cambio perceive` reads and validates its images with (read_image_file reads the file
// and calls it). Whatever the bytes, it returns an image within the documented limits or throws
// ImageFileError; a crash, a sanitizer report, a leak or an allocation past libFuzzer's
// -malloc_limit_mb is a bug. Crashes found become cases in tests/apps/image_files_test.cpp.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "image_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  try {
    const cambio::hal::Image image =
        cambio::app::decode_image(bytes, "fuzz.png", cambio::hal::PixelFormat::kGrey8);
    const bool within_limits =
        image.width_px >= 1 && image.height_px >= 1 &&
        image.width_px <= cambio::app::kMaxImageSidePx &&
        image.height_px <= cambio::app::kMaxImageSidePx &&
        static_cast<std::int64_t>(image.width_px) * image.height_px <=
            cambio::app::kMaxImagePixels &&
        image.pixels.size() == static_cast<std::size_t>(image.width_px) * image.height_px;
    if (!within_limits) std::abort();
  } catch (const cambio::app::ImageFileError&) {
    // Refused with a message: the expected outcome for most inputs.
  }
  // The header reader alone must never read past the bytes it is given.
  (void)cambio::app::read_image_header(bytes);
  return 0;
}
