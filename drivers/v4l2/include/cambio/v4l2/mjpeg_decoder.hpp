#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "cambio/hal/image.hpp"
#include "cambio/hal/status.hpp"

namespace cambio::v4l2 {

/// Decodes a camera's Motion-JPEG frames (V4L2_PIX_FMT_MJPEG: each buffer one baseline JPEG)
/// with libjpeg-turbo, straight into the rows of an image whose size and format were set at
/// configure: grey8 takes the JPEG's luma as it is (JPEG's Y'CbCr is full range), rgb8 libjpeg's
/// colour conversion. Frames without Huffman tables (the AVI1 form most UVC cameras send) use
/// JPEG's standard tables, as libjpeg-turbo supplies them.
///
/// Allocation: the decompressor is created once, but libjpeg takes each frame's working memory
/// (its per-image pools, a few kB to a few hundred kB with the image's width) from malloc and
/// returns it when the frame ends; its memory manager takes no caller-supplied pool. That is the
/// camera loop's one allocation with MJPEG, a fixed number of blocks per frame
/// (v4l2_capture_test measures it); GREY and YUYV allocate nothing.
class MjpegDecoder {
 public:
  MjpegDecoder();
  ~MjpegDecoder();
  MjpegDecoder(const MjpegDecoder&) = delete;
  MjpegDecoder& operator=(const MjpegDecoder&) = delete;

  /// Decodes `frame` into `out` (its size and format unchanged). kRejected for bytes that are
  /// not a JPEG, a damaged or cut-short frame (a USB transfer that lost its end), or a frame of
  /// another size than `out`; `out` may then hold part of the frame. Never throws.
  hal::Status decode(std::span<const std::uint8_t> frame, hal::Image& out) noexcept;

  /// libjpeg's state (mjpeg_decoder.cpp).
  struct Decompressor;

 private:
  std::unique_ptr<Decompressor> decompressor_;
};

}  // namespace cambio::v4l2
