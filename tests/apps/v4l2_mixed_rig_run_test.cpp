// A mixed rig through the main job: the pan-tilt's joints in the sim and its camera on the v4l2
// backend (a free-running fake device, tests/drivers/v4l2/fake_video_device.hpp, in place of
// the kernel's), registered as `cambio run` registers it. The camera loop grabs its frames; a
// camera unplugged mid-run is a camera fault the run reports and ends on as a device fault
// (`cambio run` exits 3 on fault_latched_at_end).

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include "builtin_backends.hpp"
#include "cambio/config/experiment_config.hpp"
#include "cambio/v4l2/v4l2_backend.hpp"
#include "cambio/v4l2/v4l2_rig_from_config.hpp"
#include "fake_video_device.hpp"
#include "main_job.hpp"

namespace cambio::testing {
namespace {

constexpr std::int64_t kPeriodNs = 33'333'333;  // 30 Hz

config::ExperimentConfig pan_tilt_with_v4l2_camera() {
  return config::load_experiment(
      std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/experiments/pan_tilt_hold.yaml",
      {{"rig.cameras.camera.backend", "v4l2"},
       {"rig.cameras.camera.device", "/dev/video0"},
       {"rig.cameras.camera.pixel_format", "YUYV"},
       {"rig.cameras.camera.frame_rate_hz", "30"},
       {"rig.cameras.camera.width_px", "64"},
       {"rig.cameras.camera.height_px", "48"},
       {"rig.cameras.camera.focal_px", "55"},
       {"rig.cameras.camera.principal_point_px", "[31.5, 23.5]"},
       {"experiment.duration_s", "0.6"}});
}

/// The builtin backends, with "v4l2" opening a free-running fake instead of /dev/video0.
struct MixedRig {
  config::ExperimentConfig experiment = pan_tilt_with_v4l2_camera();
  hal::BackendFactory factory;
  std::atomic<v4l2::test::FakeVideoDevice*> device{nullptr};

  MixedRig() {
    app::register_builtin_backends(factory, experiment);
    v4l2::register_v4l2_backend(
        factory, v4l2::v4l2_rig_from_config(experiment.rig),
        [this](const std::string& path) -> std::unique_ptr<v4l2::VideoDevice> {
          const v4l2::DeviceModes modes = {
              {v4l2::kFourccYuyv, {v4l2::FrameSizeOffer::discrete(64, 48, {{1, 30}})}}};
          auto fake = std::make_unique<v4l2::test::FakeVideoDevice>(modes, path);
          fake->free_running_period_ns = kPeriodNs;
          device = fake.get();
          return fake;
        });
  }
};

TEST(V4l2MixedRigRun, SimJointsWithAV4l2CameraRunTheMainJobsLoops) {
  MixedRig rig;
  app::MainJob job(rig.experiment, rig.factory);
  EXPECT_TRUE(job.realtime()) << "a v4l2 camera paces the run by the wall clock";
  const std::atomic<bool> stop{false};
  const app::MainJobResult result = job.run(stop, [](double, double) {});
  // 0.6 s of a 30 Hz camera: about 18 frames, each grabbed once (the camera loop runs at 30 Hz
  // too, so a few may be superseded).
  EXPECT_GE(result.camera_frames, 10u);
  EXPECT_LE(result.camera_frames, 20u);
  EXPECT_FALSE(result.fault_latched_at_end);
  EXPECT_TRUE(result.camera_faults.empty());
}

TEST(V4l2MixedRigRun, ACameraUnpluggedMidRunIsAFaultTheRunEndsOn) {
  MixedRig rig;
  app::MainJob job(rig.experiment, rig.factory);
  std::thread unplug([&rig] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    rig.device.load()->gone = true;
  });
  const std::atomic<bool> stop{false};
  const app::MainJobResult result = job.run(stop, [](double, double) {});
  unplug.join();
  EXPECT_GT(result.camera_frames, 0u);
  EXPECT_TRUE(result.fault_latched_at_end);
  ASSERT_EQ(result.camera_faults.size(), 1u);
  EXPECT_EQ(result.camera_faults[0],
            "v4l2: camera 'camera' on /dev/video0 was unplugged (ENODEV): camera fault");
}

}  // namespace
}  // namespace cambio::testing
