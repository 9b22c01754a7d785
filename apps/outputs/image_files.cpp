#include "image_files.hpp"

#include <algorithm>
#include <cctype>
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
// must begin with FF D8 FF, the signature OpenCV chooses its JPEG decoder by (see decode_image).
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
  return ImageHeader{ImageContainer::kPnm, *width, *height};
}

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

}  // namespace

// Each container is recognised by the very signature OpenCV's decoder for it checks (PNG: the 8
// bytes, JPEG: FF D8 FF, PxM: 'P', a digit, a blank), and no decoder OpenCV tries before it
// shares those first bytes, so imdecode, which takes the first decoder whose signature matches,
// decodes with the decoder of the container read here. Anything looser lets another decoder in:
// fuzz_image_read found "FF D8 8A ..." with "DICM" at byte 128, which OpenCV handed to GDCM's
// DICOM reader, and that aborts on a malformed file.
std::optional<ImageHeader> read_image_header(std::span<const std::uint8_t> bytes) {
  if (auto header = png_header(bytes)) return header;
  if (auto header = jpeg_header(bytes)) return header;
  return pnm_header(bytes);
}

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
  const char* container = container_name(header->container);
  cv::Mat raw;
  try {
    const cv::Mat encoded(1, static_cast<int>(bytes.size()), CV_8U,
                          const_cast<std::uint8_t*>(bytes.data()));
    const CerrSilenced silenced;
    raw = cv::imdecode(encoded, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  } catch (const cv::Exception&) {
    raw.release();
  }
  if (raw.empty()) {
    throw ImageFileError(name + ": a damaged " + container +
                         " file (its pixels cannot be decoded)");
  }
  // EXIF orientation may have turned the image; the decoder may disagree with the header.
  check_size(name, "decodes to", raw.cols, raw.rows);
  if (raw.depth() == CV_16U) {
    raw.convertTo(raw, CV_8U, 1.0 / 257.0);
  } else if (raw.depth() != CV_8U) {
    throw ImageFileError(name + ": unsupported sample type (expected 8 or 16 bit)");
  }
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
  if (converted.empty()) {
    throw ImageFileError(name + ": unsupported channel count " + std::to_string(channels));
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

namespace {

cv::Mat bgr_view(const hal::Image& image) {
  const int type = image.channels() == 3 ? CV_8UC3 : CV_8UC1;
  const cv::Mat view(image.height_px, image.width_px, type,
                     const_cast<std::uint8_t*>(image.pixels.data()), image.stride_bytes());
  if (image.channels() != 3) return view;
  cv::Mat bgr;
  cv::cvtColor(view, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

std::vector<std::uint8_t> encode(const cv::Mat& mat, const std::string& what) {
  std::vector<std::uint8_t> bytes;
  if (mat.empty() || !cv::imencode(".png", mat, bytes)) {
    throw ImageFileError(what + ": could not encode as PNG");
  }
  return bytes;
}

}  // namespace

std::vector<std::uint8_t> encode_png(const hal::Image& image) {
  return encode(bgr_view(image),
                std::to_string(image.width_px) + "x" + std::to_string(image.height_px) + " image");
}

std::vector<std::uint8_t> encode_png16(std::span<const std::uint16_t> samples, int width_px,
                                       int height_px) {
  if (samples.size() != static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px)) {
    throw ImageFileError("16-bit image: sample count does not match " + std::to_string(width_px) +
                         "x" + std::to_string(height_px));
  }
  const cv::Mat view(height_px, width_px, CV_16UC1, const_cast<std::uint16_t*>(samples.data()));
  return encode(view, "16-bit image");
}

}  // namespace cambio::app
