#include <cctype>
#include <string>

#include "decoded_pixels.hpp"

namespace cambio::app {

namespace {

// A sample of `max_value` scaled to 0-255, rounded to nearest (for a 16-bit file with the largest
// value 65535, round(value / 257)).
std::uint8_t scaled(std::uint32_t value, std::uint32_t max_value) {
  return static_cast<std::uint8_t>((value * 255U + max_value / 2U) / max_value);
}

}  // namespace

DecodedPixels decode_pnm_pixels(std::span<const std::uint8_t> bytes, const ImageHeader& header) {
  const bool text = bytes[1] == '2' || bytes[1] == '3';
  const int channels = bytes[1] == '3' || bytes[1] == '6' ? 3 : 1;
  DecodedPixels pixels{
      static_cast<int>(header.width_px), static_cast<int>(header.height_px), channels, {}};
  const auto max_value = static_cast<std::uint32_t>(header.pnm_max_value);
  const std::size_t count = static_cast<std::size_t>(header.width_px) *
                            static_cast<std::size_t>(header.height_px) *
                            static_cast<std::size_t>(channels);
  std::size_t at = header.pnm_samples_at;
  if (!text) {
    const std::size_t sample_bytes = max_value > 255 ? 2 : 1;  // 16-bit samples are big-endian
    if (at > bytes.size() || (bytes.size() - at) / sample_bytes < count) {
      throw DamagedPixels("the file ends before its last sample");
    }
    pixels.samples.resize(count);
    for (std::size_t i = 0; i < count; ++i, at += sample_bytes) {
      const std::uint32_t value =
          sample_bytes == 2 ? (std::uint32_t{bytes[at]} << 8) | bytes[at + 1] : bytes[at];
      if (value > max_value) {
        throw DamagedPixels("sample " + std::to_string(i) + " is " + std::to_string(value) +
                            ", above the largest value " + std::to_string(max_value));
      }
      pixels.samples[i] = scaled(value, max_value);
    }
    return pixels;
  }
  pixels.samples.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    while (at < bytes.size() && std::isspace(bytes[at]) != 0) ++at;
    std::uint32_t value = 0;
    const std::size_t start = at;
    for (; at < bytes.size() && std::isdigit(bytes[at]) != 0 && value <= max_value; ++at) {
      value = value * 10 + static_cast<std::uint32_t>(bytes[at] - '0');
    }
    if (at == start) {
      throw DamagedPixels(at >= bytes.size() ? "the file ends before its last sample"
                                             : "sample " + std::to_string(i) + " is not a number");
    }
    if (value > max_value) {
      throw DamagedPixels("sample " + std::to_string(i) + " is above the largest value " +
                          std::to_string(max_value));
    }
    pixels.samples[i] = scaled(value, max_value);
  }
  return pixels;
}

}  // namespace cambio::app
