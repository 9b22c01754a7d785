// Tests of sim/src/egl_devices.cpp and sim/src/egl_context.cpp: the EGL devices are listed, a
// context opens on the device the rig or CAMBIO_EGL_DEVICE names and renders there what Mesa's
// surfaceless platform renders, `auto` says why it fell back, and a device that is not there is
// an error that lists the devices. Mesa lists its software rasteriser (llvmpipe) as an EGL
// device, so the device path runs on a machine without a GPU.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../scoped_environment_variable.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/sim/egl_context.hpp"
#include "cambio/sim/egl_devices.hpp"
#include "cambio/sim/renderer.hpp"
#include "sim_test_support.hpp"

namespace cambio::sim {
namespace {

using cambio::testing::ScopedEnvironmentVariable;
using config::RenderDevice;

/// The first software-rasteriser device: llvmpipe, as Mesa surfaceless renders with on a
/// machine without a GPU, so the two can be compared pixel for pixel.
std::optional<EglDevice> software_device() {
  for (const auto& device : enumerate_egl_devices()) {
    if (device.software) return device;
  }
  return std::nullopt;
}

config::RenderDeviceChoice rig_choice(RenderDevice device) {
  return {device, "rig.yaml", "sim.render_device"};
}

RenderDevice index_device(int index) {
  return {RenderDevice::Kind::kIndex, index};
}

/// The vergence scene with the robot at its initial pose, its renderer on `device`.
std::unique_ptr<SimBackend> make_sim_on(const RenderDevice& device, hal::Clock& clock) {
  auto rig = sim::testing::load_shipped_rig();
  sim::testing::use_small_cameras(rig);
  rig.sim.render_device = device;
  return sim::testing::make_sim(rig, sim::testing::load_shipped_scene("vergence"), clock);
}

/// What the left eye sees, through `sim`'s renderer.
std::vector<std::uint8_t> render_left_eye(SimBackend& sim) {
  Renderer& renderer = sim.renderer();
  const auto& camera = sim.world().rig().cameras.front();
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(camera.width_px) * camera.height_px * 3);
  const Renderer::Lease lease(renderer, Renderer::Lease::Mode::kWait);
  EXPECT_TRUE(renderer.render(sim.world().camera_id(camera.name), camera.width_px, camera.height_px,
                              ViewOptions{}, rgb.data(), nullptr));
  return rgb;
}

/// The one issue of the config::ConfigError that making the shipped rig's renderer throws, as
/// the commands meet it; a failure if it throws none.
config::ConfigIssue renderer_refusal() {
  hal::ManualClock clock;
  auto sim =
      sim::testing::make_sim(sim::testing::load_shipped_rig(), sim::testing::empty_scene(), clock);
  try {
    ADD_FAILURE() << "the renderer was made on " << sim->renderer().description().egl_platform;
  } catch (const config::ConfigError& error) {
    EXPECT_EQ(error.issues().size(), 1u) << error.what();
    if (!error.issues().empty()) return error.issues()[0];
  }
  return {};
}

class EglContextTest : public ::testing::Test {
 protected:
  // A CAMBIO_EGL_DEVICE in the test's environment would override every choice made here.
  ScopedEnvironmentVariable unset_{config::kRenderDeviceVariable, std::nullopt};
};

TEST_F(EglContextTest, ListsTheDevicesMesasSoftwareRasteriserAmongThem) {
  const std::vector<EglDevice> devices = enumerate_egl_devices();
  ASSERT_FALSE(devices.empty());
  for (std::size_t i = 0; i < devices.size(); ++i) {
    EXPECT_EQ(devices[i].index, static_cast<int>(i));
    EXPECT_NE(devices[i].handle, nullptr);
    EXPECT_NE(describe_egl_devices(devices).find(devices[i].describe()), std::string::npos);
  }
  const auto software = software_device();
  ASSERT_TRUE(software.has_value())
      << "Mesa (libegl-mesa0) lists llvmpipe as a device; found " << describe_egl_devices(devices);
  if (software->node().empty()) {
    EXPECT_EQ(software->name(),
              "device " + std::to_string(software->index) + " (software rasteriser)");
  }
}

TEST_F(EglContextTest, OpensAContextOnAnExplicitDevice) {
  const auto device = software_device();
  ASSERT_TRUE(device.has_value());
  const EglContext context(rig_choice(index_device(device->index)));
  EXPECT_EQ(context.description().egl_platform, device->name());
  EXPECT_NE(context.description().gl_renderer.find("llvmpipe"), std::string::npos)
      << context.description().summary();
  EXPECT_NE(context.description().gl_vendor, "unknown");
  EXPECT_TRUE(context.description().fallback_reason.empty());
}

// Both are llvmpipe with the same state: the frames are identical byte for byte.
TEST_F(EglContextTest, ADeviceRendersWhatMesaSurfacelessRenders) {
  const auto device = software_device();
  ASSERT_TRUE(device.has_value());
  hal::ManualClock clock;
  auto device_sim = make_sim_on(index_device(device->index), clock);
  auto surfaceless_sim = make_sim_on({RenderDevice::Kind::kSurfaceless, 0}, clock);
  EXPECT_EQ(device_sim->renderer().description().egl_platform, device->name());
  EXPECT_EQ(surfaceless_sim->renderer().description().egl_platform, "Mesa surfaceless");
  const auto on_device = render_left_eye(*device_sim);
  const auto on_surfaceless = render_left_eye(*surfaceless_sim);
  ASSERT_EQ(on_device.size(), on_surfaceless.size());
  const auto differing = std::mismatch(on_device.begin(), on_device.end(), on_surfaceless.begin());
  EXPECT_TRUE(differing.first == on_device.end())
      << "first difference at byte " << differing.first - on_device.begin();
  // Not a blank frame that would match anything blank.
  EXPECT_GT(*std::max_element(on_device.begin(), on_device.end()),
            *std::min_element(on_device.begin(), on_device.end()));
}

// eglGetPlatformDisplayEXT gives every context on one device the same display: a renderer going
// away must leave the display to the others on it (it is never terminated).
TEST_F(EglContextTest, ARendererOutlivesAnotherOnTheSameDevice) {
  const auto device = software_device();
  ASSERT_TRUE(device.has_value());
  hal::ManualClock clock;
  auto first = make_sim_on(index_device(device->index), clock);
  auto second = make_sim_on(index_device(device->index), clock);
  const auto before = render_left_eye(*second);
  (void)first->renderer();
  first.reset();
  EXPECT_EQ(render_left_eye(*second), before);
}

TEST_F(EglContextTest, AutoTakesTheFirstHardwareDeviceElseFallsBackAndSaysWhy) {
  const std::vector<EglDevice> devices = enumerate_egl_devices();
  const auto hardware = std::find_if(devices.begin(), devices.end(),
                                     [](const EglDevice& device) { return !device.software; });
  const EglContext context(rig_choice(RenderDevice{}));
  const RendererDescription& description = context.description();
  if (hardware == devices.end()) {
    // This machine (no GPU): Mesa surfaceless, because every device is a software rasteriser.
    EXPECT_EQ(description.egl_platform, "Mesa surfaceless");
    EXPECT_EQ(description.fallback_reason,
              "no hardware EGL device (devices: " + describe_egl_devices(devices) + ")");
    EXPECT_NE(description.summary().find("(auto fell back: no hardware EGL device"),
              std::string::npos)
        << description.summary();
  } else if (description.fallback_reason.empty()) {
    EXPECT_EQ(description.egl_platform, hardware->name());
  } else {
    EXPECT_EQ(description.egl_platform, "Mesa surfaceless");
    EXPECT_EQ(description.fallback_reason.rfind(hardware->name() + " cannot render: ", 0), 0u)
        << description.fallback_reason;
  }
}

TEST_F(EglContextTest, AnIndexPastTheDevicesIsAnErrorListingThem) {
  const std::vector<EglDevice> devices = enumerate_egl_devices();
  const int past = static_cast<int>(devices.size());
  try {
    const EglContext context(rig_choice(index_device(past)));
    FAIL() << "device " << past << " opened";
  } catch (const config::ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1u);
    const config::ConfigIssue& issue = error.issues()[0];
    EXPECT_EQ(issue.file, "rig.yaml");
    EXPECT_EQ(issue.key_path, "sim.render_device");
    EXPECT_EQ(issue.message, "expected an EGL device index in [0, " + std::to_string(past - 1) +
                                 "], found " + std::to_string(past) +
                                 " (devices: " + describe_egl_devices(devices) +
                                 "); or set sim.render_device to auto or surfaceless");
    for (const auto& device : devices) {
      EXPECT_NE(issue.message.find(device.describe()), std::string::npos) << issue.message;
    }
  }
}

// Through the renderer, as the commands build it: the variable wins over the rig.
TEST(RenderDeviceVariable, OverridesTheRig) {
  const auto device = software_device();
  ASSERT_TRUE(device.has_value());
  const ScopedEnvironmentVariable variable(config::kRenderDeviceVariable,
                                           std::to_string(device->index));
  hal::ManualClock clock;
  auto sim = make_sim_on({RenderDevice::Kind::kSurfaceless, 0}, clock);
  EXPECT_EQ(sim->renderer().description().egl_platform, device->name());
}

TEST(RenderDeviceVariable, AnIndexPastTheDevicesNamesTheVariable) {
  const int past = static_cast<int>(enumerate_egl_devices().size());
  const ScopedEnvironmentVariable variable(config::kRenderDeviceVariable, std::to_string(past));
  const std::string text = renderer_refusal().to_string();
  EXPECT_EQ(text.rfind("environment: CAMBIO_EGL_DEVICE: expected an EGL device index in [0, ", 0),
            0u)
      << text;
  EXPECT_NE(text.find("or set CAMBIO_EGL_DEVICE to auto or surfaceless"), std::string::npos)
      << text;
}

TEST(RenderDeviceVariable, GarbageIsAConfigErrorNamingTheAcceptedValues) {
  const ScopedEnvironmentVariable variable(config::kRenderDeviceVariable, "nvidia0");
  EXPECT_EQ(renderer_refusal().to_string(),
            "environment: CAMBIO_EGL_DEVICE: expected auto, surfaceless or an EGL device index "
            "(0, 1, ...), found \"nvidia0\"");
}

}  // namespace
}  // namespace cambio::sim
