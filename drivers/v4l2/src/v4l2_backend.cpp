#include "cambio/v4l2/v4l2_backend.hpp"

#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "cambio/v4l2/kernel_video_device.hpp"
#include "cambio/v4l2/v4l2_rig_check.hpp"

namespace cambio::v4l2 {

struct V4l2Backend::CameraSlot {
  V4l2Capture capture;
  V4l2StereoPair* pair = nullptr;  // Set at configure when this camera is an eye of the pair.
  hal::Eye eye = hal::Eye::kLeft;
};

namespace {

std::string in_quotes(std::string_view name) {
  return "'" + std::string(name) + "'";
}

/// What the run holds: forwards to the backend's slot, which deactivate() reaches whatever the
/// application did with the handle.
class V4l2Camera final : public hal::Camera {
 public:
  V4l2Camera(V4l2Capture& capture, V4l2StereoPair* const& pair, const hal::Eye& eye)
      : capture_(capture), pair_(pair), eye_(eye) {}

  const hal::CameraInfo& info() const override { return capture_.info(); }

  hal::Status grab(hal::Image& out) override {
    const hal::CameraInfo& info = capture_.info();
    if (out.width_px != info.intrinsics.width_px || out.height_px != info.intrinsics.height_px ||
        out.format != info.format) {
      return hal::Status::kRejected;
    }
    return pair_ != nullptr ? pair_->grab(eye_, out) : capture_.grab_newest(out);
  }

 private:
  V4l2Capture& capture_;
  V4l2StereoPair* const& pair_;
  const hal::Eye& eye_;
};

}  // namespace

V4l2Backend::V4l2Backend(const hal::HardwareInfo& hardware, V4l2RigInfo rig,
                         const hal::BackendContext& context, DeviceOpener opener)
    : hardware_(hardware),
      rig_(std::move(rig)),
      clock_(*context.clock),
      opener_(std::move(opener)) {
  if (!opener_) throw std::invalid_argument("v4l2: no device opener given");
}

V4l2Backend::~V4l2Backend() {
  deactivate();
}

std::unique_ptr<hal::JointGroup> V4l2Backend::make_joint_group(std::string_view group_name) {
  throw hal::BackendUnavailable("v4l2: joint group " + in_quotes(group_name) +
                                ": the v4l2 backend makes cameras only");
}

std::unique_ptr<hal::TouchSensor> V4l2Backend::make_touch_sensor(std::string_view sensor_name) {
  throw hal::BackendUnavailable("v4l2: touch sensor " + in_quotes(sensor_name) +
                                ": the v4l2 backend makes cameras only");
}

std::unique_ptr<hal::Camera> V4l2Backend::make_camera(std::string_view camera_name) {
  const hal::CameraInfo* info = hardware_.find_camera(camera_name);
  const V4l2CameraSettings* settings = rig_.find(camera_name);
  if (info == nullptr) {
    throw std::runtime_error("v4l2: the rig has no camera " + in_quotes(camera_name));
  }
  if (settings == nullptr || settings->device.empty()) {
    throw std::runtime_error("v4l2: camera " + in_quotes(camera_name) + " names no device");
  }
  if (cameras_.count(camera_name) != 0) {
    throw std::runtime_error("v4l2: camera " + in_quotes(camera_name) + " was already made");
  }
  std::unique_ptr<VideoDevice> device = opener_(settings->device);
  if (device == nullptr) {
    throw DeviceError("v4l2: camera " + in_quotes(camera_name) + ": cannot open " +
                      settings->device);
  }
  auto slot = std::unique_ptr<CameraSlot>(new CameraSlot{
      V4l2Capture(*info, *settings, std::move(device), clock_), nullptr, hal::Eye::kLeft});
  auto camera = std::make_unique<V4l2Camera>(slot->capture, slot->pair, slot->eye);
  cameras_.emplace(std::string(camera_name), std::move(slot));
  return camera;
}

void V4l2Backend::configure() {
  for (auto& [name, slot] : cameras_) {
    slot->capture.configure();
    std::clog << slot->capture.describe() << '\n';
  }
  if (!hardware_.stereo) return;
  const auto left = cameras_.find(hardware_.stereo->left_camera);
  const auto right = cameras_.find(hardware_.stereo->right_camera);
  if (left == cameras_.end() || right == cameras_.end()) return;
  pair_ = std::make_unique<V4l2StereoPair>(left->second->capture, right->second->capture);
  left->second->pair = right->second->pair = pair_.get();
  left->second->eye = hal::Eye::kLeft;
  right->second->eye = hal::Eye::kRight;
}

void V4l2Backend::activate() {
  StampMapping mapping;
  mapping.anchor(clock_.now_ns(), monotonic_now_ns());
  for (auto& [name, slot] : cameras_) slot->capture.activate(mapping);
  active_ = true;
}

void V4l2Backend::deactivate() noexcept {
  if (!active_) return;
  active_ = false;
  for (auto& [name, slot] : cameras_) slot->capture.deactivate();
  try {
    for (const std::string& line : statistics()) std::clog << line << '\n';
  } catch (...) {  // A report that cannot be written must not stop the shutdown.
  }
}

void V4l2Backend::offer(hal::BackendOffers& offers) {
  offers.offer<const hal::CameraFaults>(*this);
}

std::vector<std::string> V4l2Backend::camera_faults() const {
  std::vector<std::string> faults;
  for (const auto& [name, slot] : cameras_) {
    if (std::string fault = slot->capture.fault_message(); !fault.empty()) {
      faults.push_back(std::move(fault));
    }
  }
  return faults;
}

const V4l2Capture* V4l2Backend::capture(std::string_view camera_name) const {
  const auto it = cameras_.find(camera_name);
  return it == cameras_.end() ? nullptr : &it->second->capture;
}

std::vector<std::string> V4l2Backend::statistics() const {
  std::vector<std::string> lines;
  for (const auto& [name, slot] : cameras_) {
    const CaptureCounters& counts = slot->capture.counters();
    lines.push_back("v4l2: camera " + in_quotes(name) + ": " +
                    std::to_string(counts.delivered.load()) + " frames delivered, " +
                    std::to_string(counts.dropped.load()) + " dropped, " +
                    std::to_string(counts.late.load()) + " late");
    if (const std::string fault = slot->capture.fault_message(); !fault.empty()) {
      lines.push_back(fault);
    }
  }
  if (pair_) {
    const PairingCounters& counts = pair_->counters();
    const std::uint64_t pairs = counts.pairs.load();
    char text[160];
    std::snprintf(text, sizeof text,
                  "v4l2: stereo pair: %llu pairs, skew mean %.3f ms, max %.3f ms (bound %.3f ms)",
                  static_cast<unsigned long long>(pairs),
                  pairs == 0 ? 0.0
                             : 1e-6 * static_cast<double>(counts.total_skew_ns.load()) /
                                   static_cast<double>(pairs),
                  1e-6 * static_cast<double>(counts.max_skew_ns.load()),
                  1e-6 * static_cast<double>(pair_->max_skew_ns()));
    lines.emplace_back(text);
  }
  return lines;
}

void register_v4l2_backend(hal::BackendFactory& factory, V4l2RigInfo rig, DeviceOpener opener) {
  if (!opener) {
    opener = [](const std::string& path) -> std::unique_ptr<VideoDevice> {
      return KernelVideoDevice::open(path);
    };
  }
  auto checker = [rig](const hal::HardwareInfo& hardware) { return check_v4l2_rig(hardware, rig); };
  factory.register_backend(
      std::string(V4l2Backend::kName),
      [rig, opener](const hal::HardwareInfo& hardware,
                    const hal::BackendContext& context) -> std::unique_ptr<hal::Backend> {
        return std::make_unique<V4l2Backend>(hardware, rig, context, opener);
      },
      hal::BackendTraits{.paced_by_wall_clock = true}, std::move(checker));
}

}  // namespace cambio::v4l2
