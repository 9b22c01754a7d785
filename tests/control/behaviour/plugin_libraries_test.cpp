// Loading behaviour plugins: a good one registers into the program's registry and its behaviour
// runs; a file that is no library, one built for another ABI and one whose registration throws
// are refused with the file named and nothing of theirs left in the registry.
#include "cambio/behaviour/plugin_libraries.hpp"

#include <gtest/gtest.h>

#include "recording_actions.hpp"

namespace cambio::behaviour {
namespace {

using testing::RecordingActions;

std::string what_of(const std::function<void()>& work) {
  try {
    work();
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

TEST(PluginLibrariesTest, APluginRegistersIntoTheProgramsRegistryAndItsBehaviourRuns) {
  PluginLibraries plugins;
  BehaviourRegistry registry;
  registry.add("builtin", [](BehaviourParams&) -> std::unique_ptr<Behaviour> { return nullptr; });
  plugins.load(CAMBIO_TEST_PLUGIN, registry);
  EXPECT_EQ(registry.names(), (std::vector<std::string>{"builtin", "counting", "failing"}));
  BehaviourParams params({{"every", {"3", "e.yaml:9"}}});
  {
    auto behaviour = registry.make("counting", params);
    RecordingActions actions;
    Observation observation;
    for (int i = 0; i < 7; ++i) behaviour->step(observation, actions);
    EXPECT_EQ(actions.holds, 2);
    EXPECT_EQ(behaviour->status(), "counted 7");
  }
  registry.clear();  // The factories hold the plugin's code: gone before the library closes.
}

TEST(PluginLibrariesTest, AFileThatIsNoLibraryIsNamedWithDlerror) {
  PluginLibraries plugins;
  BehaviourRegistry registry;
  const std::string message =
      what_of([&] { plugins.load("/nonexistent/libnothing.so", registry); });
  EXPECT_NE(message.find("'/nonexistent/libnothing.so'"), std::string::npos) << message;
  EXPECT_NE(message.find("cannot open shared object file"), std::string::npos) << message;
}

TEST(PluginLibrariesTest, APluginOfAnotherAbiIsRefusedWithBothVersions) {
  PluginLibraries plugins;
  BehaviourRegistry registry;
  const std::string message =
      what_of([&] { plugins.load(CAMBIO_TEST_PLUGIN_OTHER_ABI, registry); });
  EXPECT_NE(message.find("ABI version " + std::to_string(kBehaviourAbiVersion + 1)),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("this program has version " + std::to_string(kBehaviourAbiVersion)),
            std::string::npos)
      << message;
  EXPECT_TRUE(registry.names().empty());
  EXPECT_TRUE(plugins.paths().empty());
}

TEST(PluginLibrariesTest, ARegistrationThatThrowsLeavesNothingBehind) {
  PluginLibraries plugins;
  BehaviourRegistry registry;
  const std::string message = what_of([&] { plugins.load(CAMBIO_TEST_PLUGIN_THROWS, registry); });
  EXPECT_NE(message.find("refuses to register"), std::string::npos) << message;
  EXPECT_FALSE(registry.has("half_registered"));
}

TEST(PluginLibrariesTest, APluginThatThrowsSomethingElseThanAStdExceptionIsRefusedNotFatal) {
  PluginLibraries plugins;
  BehaviourRegistry registry;
  std::string message = what_of([&] { plugins.load(CAMBIO_TEST_PLUGIN_THROWS_NON_STD, registry); });
  EXPECT_NE(message.find("registering its behaviours failed"), std::string::npos) << message;
  EXPECT_FALSE(registry.has("half_registered"));

  plugins.load(CAMBIO_TEST_PLUGIN_FACTORY_THROWS_NON_STD, registry);
  ASSERT_TRUE(registry.has("throws_when_made"));
  BehaviourParams params;
  message = what_of([&] { (void)registry.make("throws_when_made", params); });
  EXPECT_NE(message.find("its factory threw"), std::string::npos) << message;
}

TEST(PluginLibrariesTest, ANameAlreadyTakenIsRefused) {
  PluginLibraries plugins;
  BehaviourRegistry registry;
  registry.add("counting", [](BehaviourParams&) -> std::unique_ptr<Behaviour> { return nullptr; });
  const std::string message = what_of([&] { plugins.load(CAMBIO_TEST_PLUGIN, registry); });
  EXPECT_NE(message.find("'counting', a name already taken"), std::string::npos) << message;
}

}  // namespace
}  // namespace cambio::behaviour
