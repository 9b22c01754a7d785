#include "image_files.hpp"

#include <opencv2/imgcodecs.hpp>

namespace cambio::app {

namespace {

// The image as OpenCV encodes it: grey as it is, without a copy; RGB copied into BGR order. The
// copy is a plain loop, not cv::cvtColor, which runs on TBB's worker threads: results are written
// at the end of a run, when memory may be short, and a TBB pool whose thread could not start
// spins forever (seen under an address-space limit) instead of failing.
cv::Mat bgr_view(const hal::Image& image) {
  const int type = image.channels() == 3 ? CV_8UC3 : CV_8UC1;
  const cv::Mat view(image.height_px, image.width_px, type,
                     const_cast<std::uint8_t*>(image.pixels.data()), image.stride_bytes());
  if (image.channels() != 3) return view;
  cv::Mat bgr(image.height_px, image.width_px, CV_8UC3);
  for (int row = 0; row < image.height_px; ++row) {
    const std::uint8_t* rgb_row = view.ptr<std::uint8_t>(row);
    std::uint8_t* bgr_row = bgr.ptr<std::uint8_t>(row);
    for (int x = 0; x < 3 * image.width_px; x += 3) {
      bgr_row[x] = rgb_row[x + 2];
      bgr_row[x + 1] = rgb_row[x + 1];
      bgr_row[x + 2] = rgb_row[x];
    }
  }
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
