// The registry's names and errors, and BehaviourParams' typed getters and their messages.
#include "cambio/behaviour/registry.hpp"

#include <gtest/gtest.h>

namespace cambio::behaviour {
namespace {

class Still final : public Behaviour {
 public:
  void step(const Observation&, Actions&) override {}
};

std::string what_of(const std::function<void()>& work) {
  try {
    work();
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

BehaviourRegistry two_behaviours() {
  BehaviourRegistry registry;
  registry.add("attention", [](BehaviourParams& p) {
    (void)p.number("dwell_s", 0.5);
    return std::make_unique<Still>();
  });
  registry.add("still", [](BehaviourParams&) { return std::make_unique<Still>(); });
  return registry;
}

TEST(BehaviourRegistryTest, AnUnknownNameListsTheRegisteredOnesAndSuggestsTheNearest) {
  const BehaviourRegistry registry = two_behaviours();
  BehaviourParams params;
  const std::string message = what_of([&] { (void)registry.make("atention", params); });
  EXPECT_EQ(message,
            "no behaviour named 'atention' (did you mean 'attention'?); registered: attention, "
            "still");
}

TEST(BehaviourRegistryTest, AParameterTheBehaviourNeverReadIsAnErrorAtItsLine) {
  const BehaviourRegistry registry = two_behaviours();
  BehaviourParams params({{"dwel_s", {"0.2", "scan.yaml:12"}}});
  const std::string message = what_of([&] { (void)registry.make("attention", params); });
  EXPECT_EQ(message,
            "scan.yaml:12: behaviour.params.dwel_s: behaviour 'attention' has no parameter of "
            "that name (did you mean 'dwell_s'?)");
}

TEST(BehaviourRegistryTest, ADuplicateNameIsRefused) {
  BehaviourRegistry registry = two_behaviours();
  EXPECT_THROW(registry.add("still", [](BehaviourParams&) { return std::make_unique<Still>(); }),
               std::invalid_argument);
}

TEST(BehaviourParamsTest, TypedGettersAndTheirErrors) {
  BehaviourParams params({{"rate", {"2.5", "f.yaml:3"}},
                          {"count", {"7", "f.yaml:4"}},
                          {"on", {"true", "f.yaml:5"}},
                          {"word", {"fast", "f.yaml:6"}}});
  EXPECT_EQ(params.number("rate", 0.0), 2.5);
  EXPECT_EQ(params.integer("count", 0), 7);
  EXPECT_TRUE(params.boolean("on", false));
  EXPECT_EQ(params.text("word", ""), "fast");
  EXPECT_EQ(params.number("absent", 1.25), 1.25);
  EXPECT_EQ(what_of([&] { (void)params.number("word", 0.0); }),
            "f.yaml:6: behaviour.params.word: expected a finite number, found 'fast'");
  EXPECT_EQ(what_of([&] { (void)params.integer("rate", 0); }),
            "f.yaml:3: behaviour.params.rate: expected an integer, found '2.5'");
  EXPECT_TRUE(params.unread_keys().empty());
}

}  // namespace
}  // namespace cambio::behaviour
