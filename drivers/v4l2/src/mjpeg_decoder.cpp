// libjpeg reports an error by calling error_exit, which must not return: it longjmps back to
// decode_into, which for that reason holds no object with a destructor.
#include "cambio/v4l2/mjpeg_decoder.hpp"

#include <csetjmp>
#include <cstdio>
// jpeglib.h needs FILE and size_t declared before it.
#include <jerror.h>
#include <jpeglib.h>

#include <new>

namespace cambio::v4l2 {

struct MjpegDecoder::Decompressor {
  jpeg_decompress_struct cinfo{};
  jpeg_error_mgr errors{};  // cinfo.err points here; on_error finds the jump through cinfo
  std::jmp_buf jump{};
  bool ended_early = false;
};

namespace {

using Decompressor = MjpegDecoder::Decompressor;

Decompressor& owner(j_common_ptr cinfo) {
  return *static_cast<Decompressor*>(cinfo->client_data);
}

void on_error(j_common_ptr cinfo) {
  std::longjmp(owner(cinfo).jump, 1);
}

// A frame cut short is filled with grey by libjpeg: it counts as damaged. Other warnings (stray
// bytes before a marker, common in cameras' MJPEG) leave the pixels whole. Nothing is printed.
void on_message(j_common_ptr cinfo, int level) {
  if (level < 0 && cinfo->err->msg_code == JWRN_JPEG_EOF) owner(cinfo).ended_early = true;
}

bool decode_into(Decompressor& d, std::span<const std::uint8_t> frame, hal::Image& out) {
  if (setjmp(d.jump) != 0) return false;
  jpeg_decompress_struct& cinfo = d.cinfo;
  d.ended_early = false;
  jpeg_mem_src(&cinfo, frame.data(), static_cast<unsigned long>(frame.size()));
  if (jpeg_read_header(&cinfo, TRUE) != JPEG_HEADER_OK) return false;
  if (static_cast<int>(cinfo.image_width) != out.width_px ||
      static_cast<int>(cinfo.image_height) != out.height_px) {
    return false;
  }
  cinfo.out_color_space = out.format == hal::PixelFormat::kGrey8 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_start_decompress(&cinfo);
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPROW row = out.row(static_cast<int>(cinfo.output_scanline));
    jpeg_read_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_decompress(&cinfo);
  return !d.ended_early;
}

}  // namespace

MjpegDecoder::MjpegDecoder() : decompressor_(std::make_unique<Decompressor>()) {
  Decompressor& d = *decompressor_;
  d.cinfo.err = jpeg_std_error(&d.errors);
  d.errors.error_exit = &on_error;
  d.errors.emit_message = &on_message;
  d.cinfo.client_data = &d;                         // kept by jpeg_create_decompress
  if (setjmp(d.jump) != 0) throw std::bad_alloc();  // libjpeg's only error here: no memory
  jpeg_create_decompress(&d.cinfo);
}

MjpegDecoder::~MjpegDecoder() {
  jpeg_destroy_decompress(&decompressor_->cinfo);
}

hal::Status MjpegDecoder::decode(std::span<const std::uint8_t> frame, hal::Image& out) noexcept {
  Decompressor& d = *decompressor_;
  if (decode_into(d, frame, out)) return hal::Status::kOk;
  // Ready for the next frame: the image's working memory goes back, the decompressor stays.
  jpeg_abort_decompress(&d.cinfo);
  return hal::Status::kRejected;
}

}  // namespace cambio::v4l2
