#pragma once

#include <cstdint>
#include <span>

#include "decoded_pixels.hpp"

namespace cambio::app {

/// The Orientation tag (0x0112) of IFD0 in the payload of a JPEG APP1 segment ("Exif\0\0" and a
/// TIFF header, little- or big-endian; EXIF 2.32, 4.6.4): 1 (as stored) to 8. 1 when the
/// segment is not EXIF, has no such tag, or the tag is malformed or out of range. Never reads
/// past `app1`.
int read_exif_orientation(std::span<const std::uint8_t> app1);

/// The pixels turned to be displayed upright, as EXIF orientation `orientation` asks: 2 mirrors,
/// 3 turns 180°, 4 flips, 5 transposes, 6 turns 90° clockwise, 7 transverses, 8 turns 90°
/// anticlockwise; 5 to 8 swap width and height.
DecodedPixels oriented(const DecodedPixels& pixels, int orientation);

}  // namespace cambio::app
