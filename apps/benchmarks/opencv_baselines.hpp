#pragma once

// What perception-bench compares the SSM with, on the whole images and with OpenCV (one thread,
// as the caller sets): the "filter everything" approach and a block-matching stereo.

#include "cambio/hal/image.hpp"
#include "cambio/perception/perception_config.hpp"

namespace cambio::app {

/// Median time, us, over `repeats` runs, of the SSM's operator set (`ops`) on both whole grey8
/// images: per sigma the six Eq. 3-5 maps by cv::sepFilter2D plus their sum (LoG), Sobel x and
/// y, and the 3x3 box, on a float copy.
double time_full_image_filter(const perception::OperatorConfig& ops, const hal::Image& left,
                              const hal::Image& right, int repeats);

/// Median time, us, over `repeats` runs, of cv::StereoBM (64 disparities, 15 px blocks) on the
/// whole grey8 pair.
double time_stereo_bm(const hal::Image& left, const hal::Image& right, int repeats);

}  // namespace cambio::app
