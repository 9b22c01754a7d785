// A behaviour plugin as an outside project writes one, built three ways (CMakeLists.txt):
// (the good one also serves tests/apps/behaviour_experiments_test.cpp)
// a good one, one built for another ABI version, one whose registration throws.
#include "cambio/behaviour/registry.hpp"

namespace {

class Counting final : public cambio::behaviour::Behaviour {
 public:
  explicit Counting(int every) : every_(every) {}
  void step(const cambio::behaviour::Observation&, cambio::behaviour::Actions& actions) override {
    if (++steps_ % every_ == 0) (void)actions.hold();
  }
  std::string status() const override { return "counted " + std::to_string(steps_); }

 private:
  int every_;
  int steps_ = 0;
};

// Throws from its step() once it has run `steps` of them (the program stops it).
class Failing final : public cambio::behaviour::Behaviour {
 public:
  explicit Failing(int steps) : steps_(steps) {}
  void step(const cambio::behaviour::Observation&, cambio::behaviour::Actions&) override {
    if (--steps_ < 0) throw std::runtime_error("the test plugin's behaviour failed on purpose");
  }

 private:
  int steps_;
};

}  // namespace

#if defined(CAMBIO_TEST_PLUGIN_OTHER_ABI)
extern "C" __attribute__((visibility("default"))) std::uint32_t cambio_behaviour_abi_version() {
  return cambio::behaviour::kBehaviourAbiVersion + 1;
}
extern "C" __attribute__((visibility("default"))) void cambio_register_behaviours(
    cambio::behaviour::BehaviourRegistry&) {}
#else
CAMBIO_BEHAVIOUR_PLUGIN(registry) {
#if defined(CAMBIO_TEST_PLUGIN_THROWS)
  registry.add("half_registered",
               [](cambio::behaviour::BehaviourParams&) { return std::make_unique<Counting>(1); });
  throw std::runtime_error("this plugin refuses to register");
#elif defined(CAMBIO_TEST_PLUGIN_THROWS_NON_STD)
  registry.add("half_registered",
               [](cambio::behaviour::BehaviourParams&) { return std::make_unique<Counting>(1); });
  throw 42;  // Not a std::exception: C++ lets a plugin throw anything.
#elif defined(CAMBIO_TEST_PLUGIN_FACTORY_THROWS_NON_STD)
  registry.add("throws_when_made",
               [](cambio::behaviour::BehaviourParams&) -> std::unique_ptr<Counting> { throw 42; });
#else
  registry.add("counting", [](cambio::behaviour::BehaviourParams& params) {
    return std::make_unique<Counting>(static_cast<int>(params.integer("every", 2)));
  });
  registry.add("failing", [](cambio::behaviour::BehaviourParams& params) {
    return std::make_unique<Failing>(static_cast<int>(params.integer("steps", 3)));
  });
#endif
}
#endif
