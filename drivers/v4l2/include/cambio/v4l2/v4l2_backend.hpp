#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/hal/backend_factory.hpp"
#include "cambio/hal/camera_faults.hpp"
#include "cambio/v4l2/v4l2_camera_settings.hpp"
#include "cambio/v4l2/v4l2_capture.hpp"
#include "cambio/v4l2/v4l2_stereo_pair.hpp"
#include "cambio/v4l2/video_device.hpp"

namespace cambio::v4l2 {

/// Opens a device node (KernelVideoDevice::open by default; a fake in the tests).
using DeviceOpener = std::function<std::unique_ptr<VideoDevice>(const std::string& path)>;

/// The "v4l2" backend: cameras on Video4Linux2 capture devices (USB UVC, CSI), one
/// V4l2Capture per camera; the rig's stereo pair, when both eyes are here, pairs by timestamp.
/// Makes no joint group or touch sensor. configure() prints each camera's negotiated mode and
/// controls read back; deactivate() prints each camera's frame counts, the pairing skew and any
/// fault; it offers hal::CameraFaults, so a camera unplugged mid-run ends the run as a device
/// fault (exit 3).
class V4l2Backend final : public hal::Backend, public hal::CameraFaults {
 public:
  static constexpr std::string_view kName = "v4l2";

  V4l2Backend(const hal::HardwareInfo& hardware, V4l2RigInfo rig,
              const hal::BackendContext& context, DeviceOpener opener);
  ~V4l2Backend() override;

  std::unique_ptr<hal::JointGroup> make_joint_group(std::string_view group_name) override;
  /// Opens the camera's device (throws DeviceError naming it).
  std::unique_ptr<hal::Camera> make_camera(std::string_view camera_name) override;
  std::unique_ptr<hal::TouchSensor> make_touch_sensor(std::string_view sensor_name) override;

  void configure() override;
  void activate() override;
  void deactivate() noexcept override;
  std::vector<hal::BackendLoop> loops() override { return {}; }
  void offer(hal::BackendOffers& offers) override;
  std::vector<std::string> camera_faults() const override;

  /// A camera's stream, for tests and reports; null when not made here.
  const V4l2Capture* capture(std::string_view camera_name) const;
  /// The stereo pair, when both its eyes are made here (after configure()).
  const V4l2StereoPair* stereo_pair() const { return pair_.get(); }

  /// Each camera's counts and the pairing's skew, one line each.
  std::vector<std::string> statistics() const;

 private:
  struct CameraSlot;
  const hal::HardwareInfo& hardware_;
  V4l2RigInfo rig_;
  hal::Clock& clock_;
  DeviceOpener opener_;
  std::map<std::string, std::unique_ptr<CameraSlot>, std::less<>> cameras_;
  std::unique_ptr<V4l2StereoPair> pair_;
  bool active_ = false;
};

/// Registers "v4l2" with its check (check_v4l2_rig); paced by the wall clock (its devices run
/// in real time). `opener` defaults to KernelVideoDevice::open.
void register_v4l2_backend(hal::BackendFactory& factory, V4l2RigInfo rig, DeviceOpener opener = {});

}  // namespace cambio::v4l2
