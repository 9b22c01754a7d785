#include "peak_rss.hpp"

#include <sys/resource.h>

namespace cambio::app {

long peak_rss_kib() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return usage.ru_maxrss;  // KiB on Linux.
}

}  // namespace cambio::app
