// libFuzzer's entry point for one target: CAMBIO_FUZZ_ENTRY names its body in fuzz_targets.hpp
// (CMakeLists.txt builds this file once per target).
#include <cstddef>
#include <cstdint>

#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return CAMBIO_FUZZ_ENTRY(data, size);
}
