#include "cambio/runtime/executor.hpp"

#include <stdexcept>
#include <string>

namespace cambio::runtime {

std::vector<LiveLoopSample> Executor::live_statistics() {
  std::vector<LiveLoopSample> samples = live_names_;
  for (std::size_t i = 0; i < samples.size(); ++i) live_[i].read_and_reset(samples[i]);
  return samples;
}

void Executor::add_live_loop(std::string name, double rate_hz) {
  live_.emplace_back();
  LiveLoopSample sample;
  sample.name = std::move(name);
  sample.rate_hz = rate_hz;
  live_names_.push_back(std::move(sample));
}

void validate(const ScheduledLoop& scheduled, const char* executor_name) {
  const std::string prefix = std::string(executor_name) + " executor: ";
  if (scheduled.loop == nullptr) throw std::invalid_argument(prefix + "null loop");
  const std::string loop = "loop '" + scheduled.loop->name() + "'";
  if (!(scheduled.schedule.rate_hz > 0.0)) {
    throw std::invalid_argument(prefix + loop + " has rate_hz <= 0");
  }
  if (scheduled.schedule.priority < 0 || scheduled.schedule.priority > 99) {
    throw std::invalid_argument(prefix + loop + " has priority outside 0..99");
  }
}

}  // namespace cambio::runtime
