#include "cambio/v4l2/device_modes.hpp"

namespace cambio::v4l2 {

std::string fourcc_text(std::uint32_t code) {
  std::string text;
  for (int shift = 0; shift < 32; shift += 8) {
    const char c = static_cast<char>((code >> shift) & 0xFFu);
    text += (c >= 0x20 && c < 0x7F) ? c : '?';
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

bool FrameSizeOffer::contains(int width_px, int height_px) const {
  const auto on_steps = [](int value, int lo, int hi, int step) {
    if (value < lo || value > hi) return false;
    return step <= 0 || (value - lo) % step == 0;
  };
  return on_steps(width_px, min_width_px, max_width_px, step_width_px) &&
         on_steps(height_px, min_height_px, max_height_px, step_height_px);
}

}  // namespace cambio::v4l2
