#include "link_messages.hpp"

#include <cmath>
#include <cstring>

namespace cambio::ros2 {
namespace {

cambio_msgs_msg_dds__LevelGeometry_ to_message(const perception::LevelGeometry& in) {
  return {in.scale_px, in.origin_x_px, in.origin_y_px, in.fraction_inside};
}
perception::LevelGeometry from_message(const cambio_msgs_msg_dds__LevelGeometry_& in) {
  return {in.scale_px, in.origin_x_px, in.origin_y_px, in.fraction_inside};
}

cambio_msgs_msg_dds__Moments_ to_message(const perception::Moments& in) {
  return {in.valid,    in.area_px2, in.centroid_x_px,   in.centroid_y_px, in.mu20_px2,
          in.mu02_px2, in.mu11_px2, in.orientation_rad, in.eccentricity};
}
perception::Moments from_message(const cambio_msgs_msg_dds__Moments_& in) {
  return {in.valid,    in.area_px2, in.centroid_x_px,   in.centroid_y_px, in.mu20_px2,
          in.mu02_px2, in.mu11_px2, in.orientation_rad, in.eccentricity};
}

cambio_msgs_msg_dds__LevelDisparity_ to_message(const perception::LevelDisparity& in) {
  return {in.searched,      in.valid,         in.at_range_edge, in.aperture,    in.x_structure,
          in.disparity_px,  in.confidence,    in.peak_score,    in.texture_rms, in.scale_px,
          in.search_min_px, in.search_max_px, in.moved_windows};
}
perception::LevelDisparity from_message(const cambio_msgs_msg_dds__LevelDisparity_& in) {
  return {in.searched,      in.valid,         in.at_range_edge, in.aperture,    in.x_structure,
          in.disparity_px,  in.confidence,    in.peak_score,    in.texture_rms, in.scale_px,
          in.search_min_px, in.search_max_px, in.moved_windows};
}

cambio_msgs_msg_dds__LevelMotion_ to_message(const perception::LevelMotion& in) {
  return {in.valid,        in.flow_x_px,  in.flow_y_px,      in.min_eigenvalue,
          in.residual_rms, in.iterations, in.max_eigenvalue, in.gradient_orientation_rad};
}
perception::LevelMotion from_message(const cambio_msgs_msg_dds__LevelMotion_& in) {
  return {in.valid,        in.flow_x_px,  in.flow_y_px,      in.min_eigenvalue,
          in.residual_rms, in.iterations, in.max_eigenvalue, in.gradient_orientation_rad};
}

cambio_msgs_msg_dds__FixatedRegion_ to_message(const perception::FixatedRegion& in) {
  return {in.valid,   in.clipped,  in.cells,  in.centroid_x_px, in.centroid_y_px,
          in.left_px, in.right_px, in.top_px, in.bottom_px};
}

bool finite_in(double value, double low, double high) {
  return std::isfinite(value) && value >= low && value <= high;
}

// A received bounded sequence of at most `levels` elements, converted into `out`.
template <typename Sequence, typename Out>
bool copy_levels(const Sequence& in, int levels, Out& out) {
  if (in._length > static_cast<std::uint32_t>(levels) || (in._length > 0 && in._buffer == nullptr))
    return false;
  for (std::uint32_t k = 0; k < in._length; ++k) out[k] = from_message(in._buffer[k]);
  return true;
}

}  // namespace

SsmSummaryMessage::SsmSummaryMessage(std::string frame_id) : frame_id_(std::move(frame_id)) {
  message_.header.frame_id = frame_id_.data();
}

const cambio_msgs_msg_dds__SsmSummary_& SsmSummaryMessage::fill(
    const perception::SsmSummary& summary, RosTime stamp) {
  cambio_msgs_msg_dds__SsmSummary_& m = message_;
  m.header.stamp = {stamp.sec, stamp.nanosec};
  m.pairs_processed = summary.sequence;
  const auto levels =
      static_cast<std::uint32_t>(std::clamp(summary.levels, 0, static_cast<int>(kMaxLevels)));
  m.levels = static_cast<std::int32_t>(levels);
  for (std::size_t eye = 0; eye < 2; ++eye) {
    m.fixation_x_px[eye] = summary.fixation[eye].x;
    m.fixation_y_px[eye] = summary.fixation[eye].y;
    for (std::size_t k = 0; k < levels; ++k) {
      geometry_[eye][k] = to_message(summary.geometry[eye][k]);
      moments_[eye][k] = to_message(summary.moments[eye][k]);
    }
  }
  m.left_geometry = {levels, levels, geometry_[0].data(), false};
  m.right_geometry = {levels, levels, geometry_[1].data(), false};
  m.left_moments = {levels, levels, moments_[0].data(), false};
  m.right_moments = {levels, levels, moments_[1].data(), false};

  const perception::DisparityResult& d = summary.disparity;
  const auto disparity_levels =
      static_cast<std::uint32_t>(std::clamp(d.levels, 0, static_cast<int>(kMaxLevels)));
  for (std::size_t k = 0; k < disparity_levels; ++k) {
    disparity_levels_[k] = to_message(d.per_level[k]);
  }
  m.disparity = {d.valid,
                 d.disparity_px,
                 d.confidence,
                 d.level,
                 static_cast<std::int32_t>(disparity_levels),
                 d.candidates,
                 d.scan_window_tier,
                 {disparity_levels, disparity_levels, disparity_levels_.data(), false}};
  for (std::size_t eye = 0; eye < 2; ++eye) {
    const perception::MotionResult& in = summary.motion[eye];
    for (std::size_t k = 0; k < levels; ++k) motion_levels_[eye][k] = to_message(in.per_level[k]);
    m.motion[eye] = {in.valid,
                     in.fixation_changed,
                     in.flow_x_px,
                     in.flow_y_px,
                     in.level,
                     {levels, levels, motion_levels_[eye].data(), false},
                     in.key_valid,
                     in.key_flow_x_px,
                     in.key_flow_y_px,
                     in.frame,
                     in.key_frame,
                     in.one_directional,
                     in.gradient_orientation_rad};
  }
  const perception::SsmTimings& t = summary.timings;
  m.timings = {t.retina_us,  t.features_us, t.disparity_us, t.motion_us,
               t.moments_us, t.total_us,    t.region_us};
  m.region = to_message(summary.region);
  return m;
}

std::string summary_from_message(const cambio_msgs_msg_dds__SsmSummary_& m,
                                 std::int64_t epoch_offset_ns, perception::SsmSummary& out) {
  constexpr auto kLevels = static_cast<int>(kMaxLevels);
  if (m.levels < 0 || m.levels > kLevels) {
    return "levels " + std::to_string(m.levels) + ", a retina has 0 to " + std::to_string(kLevels);
  }
  out = perception::SsmSummary{};
  out.stamp_ns = from_ros_time({m.header.stamp.sec, m.header.stamp.nanosec}, epoch_offset_ns);
  out.levels = m.levels;
  for (std::size_t eye = 0; eye < 2; ++eye) {
    out.fixation[eye] = {m.fixation_x_px[eye], m.fixation_y_px[eye]};
  }
  if (!copy_levels(m.left_geometry, m.levels, out.geometry[0]) ||
      !copy_levels(m.right_geometry, m.levels, out.geometry[1]) ||
      !copy_levels(m.left_moments, m.levels, out.moments[0]) ||
      !copy_levels(m.right_moments, m.levels, out.moments[1])) {
    return "per-level geometry or moments for more levels than the " + std::to_string(m.levels) +
           " it has";
  }
  const cambio_msgs_msg_dds__DisparityResult_& d = m.disparity;
  if (d.levels < 0 || d.levels > kLevels || d.level < -1 || d.level >= kLevels ||
      !copy_levels(d.per_level, d.levels, out.disparity.per_level)) {
    return "disparity levels out of range";
  }
  if (!std::isfinite(d.disparity_px) || !finite_in(d.confidence, 0.0, 1.0)) {
    return "disparity " + std::to_string(d.disparity_px) + " px at confidence " +
           std::to_string(d.confidence) + ": not a finite disparity with a confidence in [0, 1]";
  }
  out.disparity.valid = d.valid;
  out.disparity.disparity_px = d.disparity_px;
  out.disparity.confidence = d.confidence;
  out.disparity.level = d.level;
  out.disparity.levels = d.levels;
  out.disparity.candidates = d.candidates;
  out.disparity.scan_window_tier = d.scan_window_tier;
  for (std::size_t eye = 0; eye < 2; ++eye) {
    const cambio_msgs_msg_dds__MotionResult_& in = m.motion[eye];
    perception::MotionResult& motion = out.motion[eye];
    if (in.level < -1 || in.level >= kLevels ||
        !copy_levels(in.per_level, kLevels, motion.per_level)) {
      return "motion levels out of range";
    }
    if (!std::isfinite(in.flow_x_px) || !std::isfinite(in.flow_y_px) ||
        !std::isfinite(in.key_flow_x_px) || !std::isfinite(in.key_flow_y_px) ||
        !std::isfinite(in.gradient_orientation_rad)) {
      return "an image motion or gradient orientation that is not a finite number";
    }
    motion.valid = in.valid;
    motion.fixation_changed = in.fixation_changed;
    motion.flow_x_px = in.flow_x_px;
    motion.flow_y_px = in.flow_y_px;
    motion.level = in.level;
    motion.key_valid = in.key_valid;
    motion.key_flow_x_px = in.key_flow_x_px;
    motion.key_flow_y_px = in.key_flow_y_px;
    motion.frame = in.frame;
    motion.key_frame = in.key_frame;
    motion.one_directional = in.one_directional;
    motion.gradient_orientation_rad = in.gradient_orientation_rad;
  }
  const cambio_msgs_msg_dds__SsmTimings_& t = m.timings;
  out.timings = {t.retina_us,  t.features_us, t.disparity_us, t.motion_us,
                 t.moments_us, t.total_us,    t.region_us};
  const cambio_msgs_msg_dds__FixatedRegion_& r = m.region;
  if (r.valid &&
      (r.cells <= 0 || !std::isfinite(r.centroid_x_px) || !std::isfinite(r.centroid_y_px) ||
       !std::isfinite(r.left_px) || !std::isfinite(r.right_px) || !std::isfinite(r.top_px) ||
       !std::isfinite(r.bottom_px))) {
    return "a fixated region of " + std::to_string(r.cells) +
           " cells whose centre or bounds are not finite numbers";
  }
  out.region = {r.valid,   r.clipped,  r.cells,  r.centroid_x_px, r.centroid_y_px,
                r.left_px, r.right_px, r.top_px, r.bottom_px};
  return "";
}

cambio_msgs_msg_dds__SsmRequest_ request_message(const perception::SsmRequest& request,
                                                 RosTime stamp) {
  cambio_msgs_msg_dds__SsmRequest_ m{};
  m.header.stamp = {stamp.sec, stamp.nanosec};
  m.header.frame_id = const_cast<char*>("");
  m.fixation_set = request.fixation_set;
  for (std::size_t eye = 0; eye < 2; ++eye) {
    m.fixation_x_px[eye] = request.fixation[eye].x;
    m.fixation_y_px[eye] = request.fixation[eye].y;
  }
  m.maps = request.features.maps;
  m.disparity = request.features.disparity;
  m.motion = request.features.motion;
  m.moments = request.features.moments;
  m.region = request.features.region;
  return m;
}

std::string request_from_message(const cambio_msgs_msg_dds__SsmRequest_& m,
                                 const hal::CameraIntrinsics& image, perception::SsmRequest& out) {
  if (m.fixation_set) {
    for (std::size_t eye = 0; eye < 2; ++eye) {
      const int x = m.fixation_x_px[eye];
      const int y = m.fixation_y_px[eye];
      if (x < -image.width_px || x > 2 * image.width_px || y < -image.height_px ||
          y > 2 * image.height_px) {
        return std::string(eye == 0 ? "left" : "right") + " fixation (" + std::to_string(x) + ", " +
               std::to_string(y) + ") px lies more than an image's size outside the " +
               std::to_string(image.width_px) + "x" + std::to_string(image.height_px) + " image";
      }
    }
  }
  out = perception::SsmRequest{};
  out.fixation_set = m.fixation_set;
  for (std::size_t eye = 0; eye < 2; ++eye) {
    out.fixation[eye] = {m.fixation_x_px[eye], m.fixation_y_px[eye]};
  }
  out.features.maps = m.maps;
  out.features.disparity = m.disparity;
  out.features.motion = m.motion;
  out.features.moments = m.moments;
  out.features.region = m.region;
  return "";
}

sensor_msgs_msg_dds__Image_ image_message(const hal::Image& image, const std::string& frame_id,
                                          RosTime stamp) {
  sensor_msgs_msg_dds__Image_ message{};
  message.header.stamp = {stamp.sec, stamp.nanosec};
  message.header.frame_id = const_cast<char*>(frame_id.c_str());
  message.height = static_cast<std::uint32_t>(image.height_px);
  message.width = static_cast<std::uint32_t>(image.width_px);
  message.encoding = const_cast<char*>(image.format == hal::PixelFormat::kRgb8 ? "rgb8" : "mono8");
  message.is_bigendian = 0;
  message.step = static_cast<std::uint32_t>(image.stride_bytes());
  const auto size = static_cast<std::uint32_t>(image.pixels.size());
  // Borrowed: the writer serializes before dds_write returns.
  message.data =
      dds_sequence_uint8{size, size, const_cast<std::uint8_t*>(image.pixels.data()), false};
  return message;
}

std::string image_from_message(const sensor_msgs_msg_dds__Image_& m, const hal::CameraInfo& camera,
                               std::int64_t epoch_offset_ns, hal::Image& out) {
  const hal::CameraIntrinsics& in = camera.intrinsics;
  if (m.width != static_cast<std::uint32_t>(in.width_px) ||
      m.height != static_cast<std::uint32_t>(in.height_px)) {
    return std::to_string(m.width) + "x" + std::to_string(m.height) + " image, camera '" +
           camera.name + "' gives " + std::to_string(in.width_px) + "x" +
           std::to_string(in.height_px);
  }
  const char* expected = camera.format == hal::PixelFormat::kRgb8 ? "rgb8" : "mono8";
  const char* encoding = m.encoding != nullptr ? m.encoding : "";
  if (std::strncmp(encoding, expected, 16) != 0) {
    return std::string("encoding '") + std::string(encoding, strnlen(encoding, 32)) +
           "', camera '" + camera.name + "' gives " + expected;
  }
  const std::size_t row_bytes = static_cast<std::size_t>(in.width_px) *
                                static_cast<std::size_t>(hal::channels_of(camera.format));
  if (m.step != row_bytes || m.data._length != row_bytes * static_cast<std::size_t>(in.height_px) ||
      m.data._buffer == nullptr) {
    return "step " + std::to_string(m.step) + " and " + std::to_string(m.data._length) +
           " bytes of data, expected " + std::to_string(row_bytes) + " and " +
           std::to_string(row_bytes * static_cast<std::size_t>(in.height_px));
  }
  if (out.width_px != in.width_px || out.height_px != in.height_px || out.format != camera.format) {
    out.resize(in.width_px, in.height_px, camera.format);  // Only before the first image.
  }
  std::memcpy(out.pixels.data(), m.data._buffer, m.data._length);
  out.stamp_ns = from_ros_time({m.header.stamp.sec, m.header.stamp.nanosec}, epoch_offset_ns);
  ++out.sequence;
  return "";
}

}  // namespace cambio::ros2
