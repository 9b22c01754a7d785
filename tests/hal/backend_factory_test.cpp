#include "cambio/hal/backend_factory.hpp"

#include <gtest/gtest.h>

#include <string>

#include "cambio/hal/manual_clock.hpp"

namespace cambio::hal {
namespace {

std::string refusal(const BackendFactory& factory, std::string_view backend) {
  ManualClock clock;
  try {
    (void)factory.make(backend, HardwareInfo{}, BackendContext{&clock}, "joint group 'head'");
  } catch (const BackendUnavailable& error) {
    return error.what();
  }
  return "";
}

/// A backend that records the context it was made with.
class RecordingBackend final : public Backend {
 public:
  explicit RecordingBackend(const BackendContext& made_with) : context(made_with) {}
  std::unique_ptr<JointGroup> make_joint_group(std::string_view) override { return nullptr; }
  std::unique_ptr<Camera> make_camera(std::string_view) override { return nullptr; }
  std::unique_ptr<TouchSensor> make_touch_sensor(std::string_view) override { return nullptr; }
  std::vector<BackendLoop> loops() override { return {}; }
  BackendContext context;
};

TEST(BackendFactory, DeclaredButUnbuiltBackendIsRefusedWithItsReason) {
  BackendFactory factory;
  factory.declare_unbuilt("socketcan", "its CANopen drivers are not built yet");
  const std::string message = refusal(factory, "socketcan");
  EXPECT_NE(message.find("backend 'socketcan'"), std::string::npos) << message;
  EXPECT_NE(message.find("joint group 'head'"), std::string::npos) << message;
  EXPECT_NE(message.find("not built yet"), std::string::npos) << message;
  EXPECT_FALSE(factory.has("socketcan"));
}

TEST(BackendFactory, UnknownBackendSaysWhatIsAvailable) {
  BackendFactory factory;
  factory.register_backend("sim", [](const HardwareInfo&, const BackendContext& context) {
    return std::unique_ptr<Backend>(std::make_unique<RecordingBackend>(context));
  });
  const std::string message = refusal(factory, "simm");
  EXPECT_NE(message.find("not a known backend"), std::string::npos) << message;
  EXPECT_NE(message.find("available: sim"), std::string::npos) << message;
  EXPECT_TRUE(factory.has("sim"));
  EXPECT_FALSE(factory.has("socketcan"));
  // No name is special: a name nobody declared is just unknown.
  EXPECT_NE(refusal(factory, "socketcan").find("not a known backend"), std::string::npos);
}

TEST(BackendFactory, AMistypedNameGetsADidYouMean) {
  BackendFactory factory;
  factory.register_backend("socketcan", [](const HardwareInfo&, const BackendContext&) {
    return std::unique_ptr<Backend>();
  });
  EXPECT_NE(factory.unavailable_reason("sockcan").find("did you mean 'socketcan'?"),
            std::string::npos);
  EXPECT_EQ(factory.unavailable_reason("ethercat").find("did you mean"), std::string::npos);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
}

TEST(BackendFactory, EveryBackendGetsTheRunsOneClock) {
  BackendFactory factory;
  auto maker = [](const HardwareInfo&, const BackendContext& context) {
    return std::unique_ptr<Backend>(std::make_unique<RecordingBackend>(context));
  };
  factory.register_backend("a", maker);
  factory.register_backend("b", maker);
  ManualClock clock;
  const BackendContext context{&clock, 7, false};
  auto a = factory.make("a", HardwareInfo{}, context, "camera 'left_eye'");
  auto b = factory.make("b", HardwareInfo{}, context, "joint group 'head'");
  EXPECT_EQ(static_cast<RecordingBackend&>(*a).context.clock, &clock);
  EXPECT_EQ(static_cast<RecordingBackend&>(*b).context.clock, &clock);
  EXPECT_THROW((void)factory.make("a", HardwareInfo{}, BackendContext{}, "x"),
               std::invalid_argument)
      << "a backend is never made without the run's clock";
}

TEST(BackendFactory, ABackendThatCannotFollowAGroupSaysSo) {
  ManualClock clock;
  RecordingBackend backend(BackendContext{&clock});
  JointGroupInfo group;
  group.name = "head";
  group.backend = "socketcan";
  struct NoSource final : JointStateSource {
    bool latest(std::span<JointState>) const noexcept override { return false; }
  } source;
  try {
    backend.follow_group(group, source);
    FAIL() << "follow_group did not throw";
  } catch (const BackendUnavailable& error) {
    EXPECT_NE(std::string(error.what()).find("'head'"), std::string::npos) << error.what();
  }
}

TEST(BackendFactory, CheckRunsEveryRegisteredBackendsCheckerOnTheWholeRig) {
  BackendFactory factory;
  auto maker = [](const HardwareInfo&, const BackendContext& context) {
    return std::unique_ptr<Backend>(std::make_unique<RecordingBackend>(context));
  };
  // "b" wants each group to have two joints; "a" has no checker; "c" objects to nothing.
  factory.register_backend("b", maker, {}, [](const HardwareInfo& hardware) {
    std::vector<SettingProblem> problems;
    for (const auto& group : hardware.groups) {
      if (group.joints.size() != 2) {
        problems.push_back({"groups." + group.name + ".joints", "expected 2 joints"});
      }
    }
    return problems;
  });
  factory.register_backend("a", maker);
  factory.register_backend("c", maker, {},
                           [](const HardwareInfo&) { return std::vector<SettingProblem>{}; });
  HardwareInfo hardware;
  hardware.groups.push_back({"head", "a", {"pan", "tilt"}, {}, 0.0});
  hardware.groups.push_back({"arm", "c", {"elbow"}, {}, 0.0});
  // A backend checks its settings wherever they are, not only on the groups that name it.
  const auto problems = factory.check(hardware);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].key_path, "groups.arm.joints");
  // Registering a name again without a checker drops the old one.
  factory.register_backend("b", maker);
  EXPECT_TRUE(factory.check(hardware).empty());
}

}  // namespace
}  // namespace cambio::hal
