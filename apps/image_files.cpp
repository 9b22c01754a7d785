#include "image_files.hpp"

#include <filesystem>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace cambio::app {

hal::Image read_image_file(const std::string& path, hal::PixelFormat format) {
  if (!std::filesystem::exists(path)) throw ImageFileError(path + ": no such file");
  cv::Mat raw = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  if (raw.empty()) {
    throw ImageFileError(path + ": not a readable image (expected PNG or JPEG, grey or colour)");
  }
  if (raw.depth() == CV_16U) {
    raw.convertTo(raw, CV_8U, 1.0 / 257.0);
  } else if (raw.depth() != CV_8U) {
    throw ImageFileError(path + ": unsupported sample type (expected 8 or 16 bit)");
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
    throw ImageFileError(path + ": unsupported channel count " + std::to_string(channels));
  }
  hal::Image image(converted.cols, converted.rows, format);
  for (int y = 0; y < converted.rows; ++y) {
    const auto* source = converted.ptr<std::uint8_t>(y);
    std::copy(source, source + image.stride_bytes(), image.row(y));
  }
  return image;
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

void write_png(const std::string& path, const hal::Image& image) {
  if (!cv::imwrite(path, bgr_view(image))) throw ImageFileError(path + ": could not write PNG");
}

void write_png16(const std::string& path, std::span<const std::uint16_t> samples, int width_px,
                 int height_px) {
  if (samples.size() != static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px)) {
    throw ImageFileError(path + ": sample count does not match " + std::to_string(width_px) + "x" +
                         std::to_string(height_px));
  }
  const cv::Mat view(height_px, width_px, CV_16UC1, const_cast<std::uint16_t*>(samples.data()));
  if (!cv::imwrite(path, view)) throw ImageFileError(path + ": could not write PNG");
}

}  // namespace cambio::app
