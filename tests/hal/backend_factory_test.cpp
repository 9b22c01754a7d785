#include "cambio/hal/backend_factory.hpp"

#include <gtest/gtest.h>

#include <string>

#include "cambio/config/rig_config.hpp"

namespace cambio::hal {
namespace {

std::string refusal(const BackendFactory& factory, std::string_view backend) {
  try {
    const config::RigConfig rig;
    (void)factory.make(backend, rig, BackendOptions{}, "joint group 'head'");
  } catch (const BackendUnavailable& error) {
    return error.what();
  }
  return "";
}

TEST(BackendFactory, PlannedButUnbuiltBackendIsRefusedClearly) {
  BackendFactory factory;
  const std::string message = refusal(factory, "socketcan");
  EXPECT_NE(message.find("backend 'socketcan'"), std::string::npos) << message;
  EXPECT_NE(message.find("joint group 'head'"), std::string::npos) << message;
  EXPECT_NE(message.find("not built yet"), std::string::npos) << message;
}

TEST(BackendFactory, UnknownBackendSaysWhatIsAvailable) {
  BackendFactory factory;
  factory.register_backend("sim", [](const config::RigConfig&, const BackendOptions&) {
    return std::unique_ptr<Backend>();
  });
  const std::string message = refusal(factory, "simm");
  EXPECT_NE(message.find("not a known backend"), std::string::npos) << message;
  EXPECT_NE(message.find("available: sim"), std::string::npos) << message;
  EXPECT_TRUE(factory.has("sim"));
  EXPECT_FALSE(factory.has("socketcan"));
}

}  // namespace
}  // namespace cambio::hal
