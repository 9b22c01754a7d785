// `cambio perception-bench`: the paper's claim, measured. On one 640x480 stereo pair: the whole
// SSM for the paper's 4 x 16 x 16 retina and its variants, a memcpy of both images (the memory
// bound), the same operator set on the full images with OpenCV and cv::StereoBM on the full pair.
// The measurement and the report are in benchmarks/perception_bench.hpp.
#include <span>
#include <string>

#include "argument_parser.hpp"
#include "command.hpp"
#include "perception_bench.hpp"

namespace cambio::app {

int run_perception_bench_command(std::span<const std::string> args) {
  ArgumentParser parser("perception-bench", "[--json] [--repeats N]");
  parser.flag("json", "print one JSON object with the medians and ratios")
      .option("repeats", "N",
              "timed runs per figure, 5 to 100000 (default 300; the 64x64 SSM and OpenCV use N/5, "
              "each memcpy-vs-SSM round N/11)");
  if (!parser.parse(args)) return kExitOk;
  PerceptionBenchOptions options;
  options.repeats = static_cast<int>(parser.integer(
      "repeats", 300, config::Range::closed(5, 100'000),
      "a median needs at least 5 runs; at 100000 a run already takes about an hour"));
  options.json = parser.flag_set("json");
  return run_perception_bench(options);
}

}  // namespace cambio::app
