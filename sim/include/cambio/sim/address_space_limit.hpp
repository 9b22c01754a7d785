#pragma once

// The process's address-space limit (RLIMIT_AS, `ulimit -v`, `prlimit --as`), which Mesa's
// software renderer runs into long before memory is short: llvmpipe maps about a gigabyte (a
// thread per core with its stack, JIT-compiled shaders, the framebuffers). Under such a limit EGL,
// MuJoCo's framebuffer and LLVM fail with messages that say nothing of memory; this says it.

#include <new>
#include <string>
#include <utility>

namespace cambio::sim {

/// Memory ran out inside MuJoCo or the renderer (an allocation MuJoCo reports as failed, or a
/// rendering failure under an address-space limit): not a device or a package. A std::bad_alloc,
/// so that it is reported as running out of memory (exit 1), never caught as a device's failure;
/// what() keeps the library's message with the limit's note.
class OutOfMemory : public std::bad_alloc {
 public:
  explicit OutOfMemory(std::string message) : message_(std::move(message)) {}
  const char* what() const noexcept override { return message_.c_str(); }

 private:
  std::string message_;
};

/// "" without a limit; else a clause to add to a rendering failure's message, e.g. "; the
/// process's address-space limit (ulimit -v) is 700 MB, and Mesa's software renderer maps about
/// 1 GB: raise the limit".
std::string address_space_limit_note();

}  // namespace cambio::sim
