// Tests of firmware_config/src/render_device.cpp: the render device's text, and
// CAMBIO_EGL_DEVICE overriding the rig's sim.render_device.
#include "cambio/config/render_device.hpp"

#include <gtest/gtest.h>

#include "../scoped_environment_variable.hpp"

namespace cambio::config {
namespace {

using cambio::testing::ScopedEnvironmentVariable;

TEST(ParseRenderDevice, NamesAndIndices) {
  EXPECT_EQ(parse_render_device("auto"), (RenderDevice{RenderDevice::Kind::kAuto, 0}));
  EXPECT_EQ(parse_render_device("surfaceless"),
            (RenderDevice{RenderDevice::Kind::kSurfaceless, 0}));
  EXPECT_EQ(parse_render_device("0"), (RenderDevice{RenderDevice::Kind::kIndex, 0}));
  EXPECT_EQ(parse_render_device("12"), (RenderDevice{RenderDevice::Kind::kIndex, 12}));
  for (const char* text : {"", " 0", "0 ", "-1", "+1", "1.5", "1e2", "AUTO", "gpu", "99999999999"})
    EXPECT_FALSE(parse_render_device(text).has_value()) << '"' << text << '"';
  EXPECT_EQ(render_device_mismatch("gpu"),
            "expected auto, surfaceless or an EGL device index (0, 1, ...), found \"gpu\"");
}

TEST(ChooseRenderDevice, TheRigsWhenTheVariableIsUnsetOrEmpty) {
  const RenderDevice rig_device{RenderDevice::Kind::kSurfaceless, 0};
  for (const auto& value : {std::optional<std::string>{}, std::optional<std::string>{""}}) {
    const ScopedEnvironmentVariable variable(kRenderDeviceVariable, value);
    const RenderDeviceChoice choice = choose_render_device(rig_device, "rig.yaml");
    EXPECT_EQ(choice.device, rig_device);
    EXPECT_EQ(choice.file, "rig.yaml");
    EXPECT_EQ(choice.key, "sim.render_device");
    EXPECT_FALSE(choice.from_environment());
  }
}

TEST(ChooseRenderDevice, TheVariableOverridesTheRig) {
  const ScopedEnvironmentVariable variable(kRenderDeviceVariable, "2");
  const RenderDeviceChoice choice =
      choose_render_device(RenderDevice{RenderDevice::Kind::kSurfaceless, 0}, "rig.yaml");
  EXPECT_EQ(choice.device, (RenderDevice{RenderDevice::Kind::kIndex, 2}));
  EXPECT_TRUE(choice.from_environment());
  EXPECT_EQ(choice.issue("x").to_string(), "environment: CAMBIO_EGL_DEVICE: x");
}

TEST(ChooseRenderDevice, ABadVariableIsAConfigErrorNamingIt) {
  const ScopedEnvironmentVariable variable(kRenderDeviceVariable, "nvidia");
  try {
    choose_render_device(RenderDevice{}, "rig.yaml");
    FAIL() << "CAMBIO_EGL_DEVICE=nvidia was taken";
  } catch (const ConfigError& error) {
    ASSERT_EQ(error.issues().size(), 1u);
    EXPECT_EQ(error.issues()[0].to_string(),
              "environment: CAMBIO_EGL_DEVICE: expected auto, surfaceless or an EGL device index "
              "(0, 1, ...), found \"nvidia\"");
  }
}

}  // namespace
}  // namespace cambio::config
