#pragma once

// perceive's contact sheet: a picture for people of what the SSM saw on one image pair.

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "cambio/hal/image.hpp"
#include "cambio/perception/sensory_servo.hpp"

namespace cambio::app {

/// The contact sheet is a picture for people: whatever the retina's size and the images' shape,
/// it fits this canvas (a 1x500 image once made it 1182x292046 px, 1 GB of pixels).
inline constexpr int kSheetMaxWidthPx = 1600;
inline constexpr int kSheetMaxHeightPx = 2400;

/// Columns: intensity and up to eight feature maps; rows: each level of each eye. Beneath, both
/// images (grey8) with each level's footprint drawn (the paper's Figure 1, bottom). Tiles are
/// enlarged to about 112 px by whole pixels and shrunk when the grid would not fit
/// kSheetMaxWidthPx x kSheetMaxHeightPx; the images are fitted into a square box under the grid.
/// A BGR picture, as OpenCV draws.
cv::Mat contact_sheet(const perception::SensoryServo& servo, const perception::SsmFrame& frame,
                      const hal::Image& left, const hal::Image& right);

/// The contact sheet as PNG file bytes (to stage in an OutputDirectory). Throws ImageFileError.
std::vector<std::uint8_t> contact_sheet_png(const perception::SensoryServo& servo,
                                            const perception::SsmFrame& frame,
                                            const hal::Image& left, const hal::Image& right);

}  // namespace cambio::app
