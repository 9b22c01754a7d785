#include "image_files.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace cambio::app {

namespace {

const char* container_name(ImageContainer container) {
  switch (container) {
    case ImageContainer::kPng:
      return "PNG";
    case ImageContainer::kJpeg:
      return "JPEG";
    case ImageContainer::kPnm:
      return "PGM/PPM";
  }
  return "image";
}

// OpenCV 4.6's imdecode writes the text of a decoder's exception to std::cerr ("imdecode_(''):
// can't read data: ...") and returns an empty image; decode_image's own message names the file
// and says what is wrong, so that text is dropped while imdecode runs.
class CerrSilenced {
 public:
  CerrSilenced() : saved_(std::cerr.rdbuf(nullptr)) {}
  ~CerrSilenced() {
    std::cerr.rdbuf(saved_);
    std::cerr.clear();
  }
  CerrSilenced(const CerrSilenced&) = delete;
  CerrSilenced& operator=(const CerrSilenced&) = delete;

 private:
  std::streambuf* saved_;
};

void check_size(const std::string& name, const char* what, std::int64_t width,
                std::int64_t height) {
  const std::string size = std::to_string(width) + "x" + std::to_string(height) + " px";
  if (width < 1 || height < 1) throw ImageFileError(name + ": " + what + " an empty image");
  if (width > kMaxImageSidePx || height > kMaxImageSidePx || width * height > kMaxImagePixels) {
    throw ImageFileError(name + ": " + what + " a " + size + " image; images are read up to " +
                         std::to_string(kMaxImageSidePx) + " px a side and " +
                         std::to_string(kMaxImagePixels >> 20) + " Mpx");
  }
}

// The file's pixels as OpenCV decodes them (its depth and channels, colour in BGR order); empty
// when they cannot be decoded.
cv::Mat decode_pixels(std::span<const std::uint8_t> bytes) {
  cv::Mat raw;
  try {
    const cv::Mat encoded(1, static_cast<int>(bytes.size()), CV_8U,
                          const_cast<std::uint8_t*>(bytes.data()));
    const CerrSilenced silenced;
    raw = cv::imdecode(encoded, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  } catch (const cv::Exception&) {
    raw.release();
  }
  return raw;
}

// 8-bit pixels of 1, 3 or 4 channels (BGR order) in the channels of `format`; empty for any
// other channel count.
cv::Mat converted_to(const cv::Mat& raw, hal::PixelFormat format) {
  cv::Mat converted;
  const int channels = raw.channels();
  if (format == hal::PixelFormat::kGrey8) {
    if (channels == 1)
      converted = raw;
    else if (channels == 3)
      cv::cvtColor(raw, converted, cv::COLOR_BGR2GRAY);
    else if (channels == 4)
      cv::cvtColor(raw, converted, cv::COLOR_BGRA2GRAY);
  } else {
    if (channels == 1)
      cv::cvtColor(raw, converted, cv::COLOR_GRAY2RGB);
    else if (channels == 3)
      cv::cvtColor(raw, converted, cv::COLOR_BGR2RGB);
    else if (channels == 4)
      cv::cvtColor(raw, converted, cv::COLOR_BGRA2RGB);
  }
  return converted;
}

}  // namespace

hal::Image decode_image(std::span<const std::uint8_t> bytes, const std::string& name,
                        hal::PixelFormat format) {
  if (bytes.empty()) throw ImageFileError(name + ": empty file");
  const std::optional<ImageHeader> header = read_image_header(bytes);
  if (!header) {
    throw ImageFileError(name +
                         ": not an image this program reads (a PNG, JPEG, PGM or PPM file with a "
                         "complete and valid header)");
  }
  check_size(name, "declares", header->width_px, header->height_px);
  cv::Mat raw = decode_pixels(bytes);
  if (raw.empty()) {
    throw ImageFileError(name + ": a damaged " + container_name(header->container) +
                         " file (its pixels cannot be decoded)");
  }
  // EXIF orientation may have turned the image; the decoder may disagree with the header.
  check_size(name, "decodes to", raw.cols, raw.rows);
  if (raw.depth() == CV_16U) {
    raw.convertTo(raw, CV_8U, 1.0 / 257.0);
  } else if (raw.depth() != CV_8U) {
    throw ImageFileError(name + ": unsupported sample type (expected 8 or 16 bit)");
  }
  const cv::Mat converted = converted_to(raw, format);
  if (converted.empty()) {
    throw ImageFileError(name + ": unsupported channel count " + std::to_string(raw.channels()));
  }
  hal::Image image(converted.cols, converted.rows, format);
  for (int y = 0; y < converted.rows; ++y) {
    const auto* source = converted.ptr<std::uint8_t>(y);
    std::copy(source, source + image.stride_bytes(), image.row(y));
  }
  return image;
}

hal::Image read_image_file(const std::string& path, hal::PixelFormat format) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw ImageFileError(path + ": no such file");
  if (std::filesystem::is_directory(status)) {
    throw ImageFileError(path + ": a directory, not an image file");
  }
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                             &std::fclose);
  if (!file) throw ImageFileError(path + ": cannot open: " + std::strerror(errno));
  // Read in pieces up to the bound: the size of a pipe or device is known only at its end.
  std::vector<std::uint8_t> bytes;
  std::vector<std::uint8_t> piece(std::size_t{1} << 20);
  for (;;) {
    const std::size_t got = std::fread(piece.data(), 1, piece.size(), file.get());
    bytes.insert(bytes.end(), piece.begin(), piece.begin() + static_cast<std::ptrdiff_t>(got));
    if (static_cast<std::int64_t>(bytes.size()) > kMaxImageFileBytes) {
      throw ImageFileError(path + ": larger than " + std::to_string(kMaxImageFileBytes >> 20) +
                           " MB, more than any image this program reads needs");
    }
    if (got < piece.size()) break;
  }
  if (std::ferror(file.get()) != 0) {
    throw ImageFileError(path + ": cannot read: " + std::strerror(errno));
  }
  return decode_image(bytes, path, format);
}

}  // namespace cambio::app
