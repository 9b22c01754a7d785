#include "cambio/runtime/executor.hpp"

#include <stdexcept>
#include <string>

namespace cambio::runtime {

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
