// Every input the fuzzers found a crash or an unbounded allocation with (regressions/<target>/,
// README.md), replayed through the same target bodies: each must now load or be refused with a
// ConfigError, within the bounds the loaders promise. Runs in the ordinary build and under the
// sanitizers of .ci/run, without libFuzzer.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "fuzz_targets.hpp"

namespace cambio::fuzz {
namespace {

using Target = int (*)(const std::uint8_t*, std::size_t);

const std::map<std::string, Target>& targets() {
  static const std::map<std::string, Target> all = {
      {"fuzz_rig", rig},
      {"fuzz_scene", scene},
      {"fuzz_experiment", experiment},
      {"fuzz_perception", perception},
      {"fuzz_override", set_override},
  };
  return all;
}

TEST(FuzzRegressions, EveryFoundInputIsHandled) {
  const std::filesystem::path root = CAMBIO_FUZZ_REGRESSIONS_DIR;
  int replayed = 0;
  for (const auto& folder : std::filesystem::directory_iterator(root)) {
    if (!folder.is_directory()) continue;
    const auto target = targets().find(folder.path().filename().string());
    ASSERT_NE(target, targets().end()) << folder.path() << " names no target of fuzz_targets.hpp";
    for (const auto& file : std::filesystem::directory_iterator(folder.path())) {
      if (!file.is_regular_file() || file.path().extension() == ".md") continue;
      std::ifstream in(file.path(), std::ios::binary);
      std::ostringstream bytes;
      bytes << in.rdbuf();
      const std::string input = bytes.str();
      SCOPED_TRACE(file.path().string());
      EXPECT_NO_THROW(
          target->second(reinterpret_cast<const std::uint8_t*>(input.data()), input.size()));
      ++replayed;
    }
  }
  RecordProperty("replayed", replayed);
}

}  // namespace
}  // namespace cambio::fuzz
