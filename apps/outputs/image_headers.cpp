#include "image_files.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <iterator>

namespace cambio::app {

namespace {

std::int64_t big_endian(std::span<const std::uint8_t> bytes, std::size_t at, int count) {
  std::int64_t value = 0;
  for (int i = 0; i < count; ++i) value = (value << 8) | bytes[at + static_cast<std::size_t>(i)];
  return value;
}

// PNG: the 8-byte signature, then the IHDR chunk (length 13) with width and height, 4 bytes each,
// big-endian (PNG specification, section 11.2.2).
std::optional<ImageHeader> png_header(std::span<const std::uint8_t> bytes) {
  static constexpr std::uint8_t kSignature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (bytes.size() < 24 || !std::equal(std::begin(kSignature), std::end(kSignature), bytes.begin()))
    return std::nullopt;
  if (big_endian(bytes, 8, 4) != 13 || std::memcmp(bytes.data() + 12, "IHDR", 4) != 0) {
    return std::nullopt;
  }
  return ImageHeader{ImageContainer::kPng, big_endian(bytes, 16, 4), big_endian(bytes, 20, 4)};
}

// JPEG: SOI, then marker segments (0xFF, the marker, a 2-byte length that counts itself) up to
// the first start-of-frame, whose bytes 3-6 are height and width (ITU-T T.81, B.2.2). Markers are
// found as libjpeg finds them: bytes before a 0xFF are skipped, 0xFF fill bytes too. The file
// must begin with FF D8 FF, the signature JPEG readers check (see read_image_header).
std::optional<ImageHeader> jpeg_header(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 4 || bytes[0] != 0xFF || bytes[1] != 0xD8 || bytes[2] != 0xFF) {
    return std::nullopt;
  }
  std::size_t i = 2;
  while (i < bytes.size()) {
    while (i < bytes.size() && bytes[i] != 0xFF) ++i;
    while (i < bytes.size() && bytes[i] == 0xFF) ++i;
    if (i >= bytes.size()) return std::nullopt;
    const std::uint8_t marker = bytes[i++];
    // 0xFF00 is a stuffed byte, TEM and RSTn stand alone: none has a length.
    if (marker == 0x00 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) continue;
    // A second SOI, the end of the image or the scan before any frame: no size to read.
    if (marker == 0xD8 || marker == 0xD9 || marker == 0xDA) return std::nullopt;
    if (i + 2 > bytes.size()) return std::nullopt;
    const auto length = static_cast<std::size_t>(big_endian(bytes, i, 2));
    if (length < 2) return std::nullopt;
    // SOF0-SOF15 except DHT (C4), JPG (C8) and DAC (CC).
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      if (length < 7 || i + 7 > bytes.size()) return std::nullopt;
      return ImageHeader{ImageContainer::kJpeg, big_endian(bytes, i + 5, 2),
                         big_endian(bytes, i + 3, 2)};
    }
    i += length;
  }
  return std::nullopt;
}

// PGM and PPM (netpbm): "P2", "P3", "P5" or "P6", then width, height and the largest sample value
// as decimal text, separated by whitespace and '#' comments that run to the end of a line.
std::optional<ImageHeader> pnm_header(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 2 || bytes[0] != 'P') return std::nullopt;
  if (bytes[1] != '2' && bytes[1] != '3' && bytes[1] != '5' && bytes[1] != '6') {
    return std::nullopt;
  }
  std::size_t i = 2;
  const auto next_number = [&]() -> std::optional<std::int64_t> {
    for (;;) {
      while (i < bytes.size() && std::isspace(bytes[i]) != 0) ++i;
      if (i >= bytes.size() || bytes[i] != '#') break;
      while (i < bytes.size() && bytes[i] != '\n' && bytes[i] != '\r') ++i;
    }
    std::int64_t value = 0;
    const std::size_t start = i;
    // Past 2^31 the value only has to stay too large: it is not accumulated further.
    for (; i < bytes.size() && std::isdigit(bytes[i]) != 0; ++i) {
      if (value < (std::int64_t{1} << 31)) value = value * 10 + (bytes[i] - '0');
    }
    if (i == start) return std::nullopt;
    // Netpbm ends each header field with whitespace. OpenCV's reader skips a '#' comment glued
    // to the digits and reads on ("5554#76666\n688" is one number to it, 5554 to a strict
    // reader): a header whose fields are not whitespace-separated is refused, never guessed.
    if (i >= bytes.size() || std::isspace(bytes[i]) == 0) return std::nullopt;
    return value;
  };
  if (bytes.size() < 3 || std::isspace(bytes[2]) == 0) return std::nullopt;
  const auto width = next_number();
  const auto height = next_number();
  const auto max_value = next_number();
  if (!width || !height || !max_value || *max_value < 1 || *max_value > 65535) {
    return std::nullopt;
  }
  return ImageHeader{ImageContainer::kPnm, *width, *height, static_cast<int>(*max_value), i + 1};
}

}  // namespace

// Each container is recognised by its full signature (PNG: the 8 bytes, JPEG: FF D8 FF, PxM: 'P',
// a digit, a blank), the same the common decoders check, and decode_image hands the bytes to the
// decoder of the container read here and no other. (When OpenCV decoded them, a looser match let
// "FF D8 8A ..." with "DICM" at byte 128 through to GDCM's DICOM reader, which aborted.)
std::optional<ImageHeader> read_image_header(std::span<const std::uint8_t> bytes) {
  if (auto header = png_header(bytes)) return header;
  if (auto header = jpeg_header(bytes)) return header;
  return pnm_header(bytes);
}

}  // namespace cambio::app
