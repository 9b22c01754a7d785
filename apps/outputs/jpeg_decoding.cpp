// JPEG pixels through libjpeg(-turbo). libjpeg reports an error by calling error_exit, which
// must not return: it longjmps back to read_jpeg, which for that reason holds no object with a
// destructor (what it fills belongs to its caller).
#include <csetjmp>
#include <cstdio>
// jpeglib.h needs FILE and size_t declared before it.
#include <jerror.h>
#include <jpeglib.h>

#include <string>

#include "decoded_pixels.hpp"
#include "exif_orientation.hpp"

namespace cambio::app {

namespace {

struct JpegErrors {
  jpeg_error_mgr manager{};  // first: libjpeg's err pointer is taken for this struct's
  std::jmp_buf jump{};
  char message[JMSG_LENGTH_MAX] = "libjpeg failed";
  bool ended_early = false;
};

void on_jpeg_error(j_common_ptr cinfo) {
  auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, errors->message);
  std::longjmp(errors->jump, 1);
}

// libjpeg goes on after a warning; the one that matters is a file cut short, whose missing
// scans libjpeg fills with grey. Other warnings (stray bytes before a marker, common in cameras'
// MJPEG) leave the pixels whole. Nothing is printed.
void on_jpeg_message(j_common_ptr cinfo, int level) {
  auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
  if (level < 0 && cinfo->err->msg_code == JWRN_JPEG_EOF) errors->ended_early = true;
}

struct JpegReader {
  jpeg_decompress_struct cinfo{};
  JpegErrors errors;
  JpegReader() {
    cinfo.err = jpeg_std_error(&errors.manager);
    errors.manager.error_exit = &on_jpeg_error;
    errors.manager.emit_message = &on_jpeg_message;
  }
  JpegReader(const JpegReader&) = delete;
  JpegReader& operator=(const JpegReader&) = delete;
  ~JpegReader() { jpeg_destroy_decompress(&cinfo); }
};

struct JpegShape {
  int width_px = 0;
  int height_px = 0;
  int components = 0;  // 1 grey, 3 RGB, 4 CMYK
  int orientation = 1;
};

bool read_jpeg(JpegReader& reader, std::span<const std::uint8_t> bytes, JpegShape& shape,
               std::vector<std::uint8_t>& raw) {
  if (setjmp(reader.errors.jump) != 0) return false;
  jpeg_decompress_struct& cinfo = reader.cinfo;
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, bytes.data(), static_cast<unsigned long>(bytes.size()));
  jpeg_save_markers(&cinfo, JPEG_APP0 + 1, 0xFFFF);
  jpeg_read_header(&cinfo, TRUE);
  switch (cinfo.jpeg_color_space) {
    case JCS_GRAYSCALE:
      cinfo.out_color_space = JCS_GRAYSCALE;
      break;
    case JCS_CMYK:
    case JCS_YCCK:
      cinfo.out_color_space = JCS_CMYK;
      break;
    default:
      cinfo.out_color_space = JCS_RGB;
      break;
  }
  jpeg_start_decompress(&cinfo);
  shape.width_px = static_cast<int>(cinfo.output_width);
  shape.height_px = static_cast<int>(cinfo.output_height);
  shape.components = cinfo.output_components;
  if (static_cast<std::int64_t>(shape.width_px) * shape.height_px > kMaxImagePixels ||
      (shape.components != 1 && shape.components != 3 && shape.components != 4)) {
    ERREXIT(&cinfo, JERR_NOT_COMPILED);
  }
  const auto stride =
      static_cast<std::size_t>(shape.width_px) * static_cast<std::size_t>(shape.components);
  raw.resize(stride * static_cast<std::size_t>(shape.height_px));
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPROW row = raw.data() + static_cast<std::size_t>(cinfo.output_scanline) * stride;
    jpeg_read_scanlines(&cinfo, &row, 1);
  }
  for (jpeg_saved_marker_ptr marker = cinfo.marker_list; marker != nullptr; marker = marker->next) {
    if (marker->marker != JPEG_APP0 + 1) continue;
    const int orientation = read_exif_orientation({marker->data, marker->data_length});
    if (orientation != 1) shape.orientation = orientation;
  }
  jpeg_finish_decompress(&cinfo);
  return true;
}

// CMYK JPEGs are in practice Adobe's, which store inverted inks: each ink is taken from white by
// the black ink's share, as OpenCV's decoder does, so that both read a CMYK file alike.
std::vector<std::uint8_t> rgb_from_adobe_cmyk(const std::vector<std::uint8_t>& cmyk) {
  std::vector<std::uint8_t> rgb(cmyk.size() / 4 * 3);
  for (std::size_t p = 0, q = 0; p + 3 < cmyk.size(); p += 4, q += 3) {
    const int k = cmyk[p + 3];
    for (std::size_t i = 0; i < 3; ++i) {
      rgb[q + i] = static_cast<std::uint8_t>(k - ((255 - cmyk[p + i]) * k >> 8));
    }
  }
  return rgb;
}

}  // namespace

DecodedPixels decode_jpeg_pixels(std::span<const std::uint8_t> bytes) {
  JpegReader reader;
  JpegShape shape;
  std::vector<std::uint8_t> raw;
  if (!read_jpeg(reader, bytes, shape, raw)) throw DamagedPixels(reader.errors.message);
  if (reader.errors.ended_early) throw DamagedPixels("the file ends before its last scan");
  DecodedPixels pixels{shape.width_px, shape.height_px, shape.components == 1 ? 1 : 3, {}};
  pixels.samples = shape.components == 4 ? rgb_from_adobe_cmyk(raw) : std::move(raw);
  return shape.orientation == 1 ? pixels : oriented(pixels, shape.orientation);
}

}  // namespace cambio::app
