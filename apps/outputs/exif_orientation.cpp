#include "exif_orientation.hpp"

#include <cstring>

namespace cambio::app {

namespace {

class TiffReader {
 public:
  TiffReader(std::span<const std::uint8_t> tiff, bool big_endian)
      : tiff_(tiff), big_endian_(big_endian) {}

  bool has(std::size_t at, std::size_t count) const {
    return at <= tiff_.size() && count <= tiff_.size() - at;
  }
  std::uint32_t read(std::size_t at, int count) const {
    std::uint32_t value = 0;
    for (int i = 0; i < count; ++i) {
      const std::uint32_t byte = tiff_[at + static_cast<std::size_t>(i)];
      value |= big_endian_ ? byte << (8 * (count - 1 - i)) : byte << (8 * i);
    }
    return value;
  }

 private:
  std::span<const std::uint8_t> tiff_;
  bool big_endian_;
};

}  // namespace

int read_exif_orientation(std::span<const std::uint8_t> app1) {
  constexpr std::size_t kExifId = 6;  // "Exif\0\0"
  if (app1.size() < kExifId + 8 || std::memcmp(app1.data(), "Exif\0\0", kExifId) != 0) return 1;
  const std::span<const std::uint8_t> tiff = app1.subspan(kExifId);
  bool big_endian = false;
  if (tiff[0] == 'M' && tiff[1] == 'M') {
    big_endian = true;
  } else if (tiff[0] != 'I' || tiff[1] != 'I') {
    return 1;
  }
  const TiffReader reader(tiff, big_endian);
  if (reader.read(2, 2) != 42) return 1;
  const std::size_t ifd = reader.read(4, 4);
  if (!reader.has(ifd, 2)) return 1;
  const std::size_t entries = reader.read(ifd, 2);
  constexpr std::uint32_t kOrientationTag = 0x0112;
  constexpr std::uint32_t kShortType = 3;
  for (std::size_t e = 0; e < entries; ++e) {
    const std::size_t entry = ifd + 2 + 12 * e;
    if (!reader.has(entry, 12)) return 1;
    if (reader.read(entry, 2) != kOrientationTag) continue;
    if (reader.read(entry + 2, 2) != kShortType || reader.read(entry + 4, 4) != 1) return 1;
    const std::uint32_t orientation = reader.read(entry + 8, 2);
    return orientation >= 1 && orientation <= 8 ? static_cast<int>(orientation) : 1;
  }
  return 1;
}

DecodedPixels oriented(const DecodedPixels& pixels, int orientation) {
  if (orientation < 2 || orientation > 8) return pixels;
  const int w = pixels.width_px;
  const int h = pixels.height_px;
  // Orientations 1-8 as a transpose followed by mirrors of the stored image's axes.
  struct Turn {
    bool transposes, mirrors_x, mirrors_y;
  };
  static constexpr Turn kTurns[8] = {
      {false, false, false}, {false, true, false}, {false, true, true}, {false, false, true},
      {true, false, false},  {true, false, true},  {true, true, true},  {true, true, false}};
  const Turn turn = kTurns[orientation - 1];
  DecodedPixels turned{turn.transposes ? h : w, turn.transposes ? w : h, pixels.channels, {}};
  turned.samples.resize(pixels.samples.size());
  const auto channels = static_cast<std::size_t>(pixels.channels);
  for (int y_out = 0; y_out < turned.height_px; ++y_out) {
    for (int x_out = 0; x_out < turned.width_px; ++x_out) {
      // The stored pixel (x, y) shown at (x_out, y_out).
      const int a = turn.transposes ? y_out : x_out;
      const int b = turn.transposes ? x_out : y_out;
      const int x = turn.mirrors_x ? w - 1 - a : a;
      const int y = turn.mirrors_y ? h - 1 - b : b;
      const std::size_t from = (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                static_cast<std::size_t>(x)) *
                               channels;
      const std::size_t to =
          (static_cast<std::size_t>(y_out) * static_cast<std::size_t>(turned.width_px) +
           static_cast<std::size_t>(x_out)) *
          channels;
      std::memcpy(turned.samples.data() + to, pixels.samples.data() + from, channels);
    }
  }
  return turned;
}

}  // namespace cambio::app
