#include "cambio/sim/address_space_limit.hpp"

#include <sys/resource.h>

namespace cambio::sim {

std::string address_space_limit_note() {
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return "";
  return "; the process's address-space limit (ulimit -v) is " +
         std::to_string(limit.rlim_cur / 1'000'000) +
         " MB, and Mesa's software renderer maps about 1 GB (a thread per core, JIT-compiled "
         "shaders): likely out of memory, raise the limit";
}

}  // namespace cambio::sim
