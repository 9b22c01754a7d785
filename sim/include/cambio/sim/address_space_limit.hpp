#pragma once

// The process's address-space limit (RLIMIT_AS, `ulimit -v`, `prlimit --as`), which Mesa's
// software renderer runs into long before memory is short: llvmpipe maps about a gigabyte (a
// thread per core with its stack, JIT-compiled shaders, the framebuffers). Under such a limit EGL,
// MuJoCo's framebuffer and LLVM fail with messages that say nothing of memory; this says it.

#include <string>

namespace cambio::sim {

/// "" without a limit; else a clause to add to a rendering failure's message, e.g. "; the
/// process's address-space limit (ulimit -v) is 700 MB, and Mesa's software renderer maps about
/// 1 GB: raise the limit".
std::string address_space_limit_note();

}  // namespace cambio::sim
