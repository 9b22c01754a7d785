#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace cambio::sim {

/// A MuJoCo error (a model that does not compile, an exhausted arena, a renderer failure),
/// carried as an exception instead of MuJoCo's default of printing, writing MUJOCO_LOG.TXT into
/// the working directory and waiting for Enter.
class MujocoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Installs the process-wide MuJoCo handlers (idempotent, thread-safe): errors throw MujocoError,
/// but a failed allocation ("could not allocate ...") throws OutOfMemory (a std::bad_alloc)
/// (libmujoco is built with unwind tables, so the exception crosses its C frames); warnings are
/// counted and the latest one kept, without allocation, so a warning raised inside mj_step stays
/// real-time safe. Every sim entry point calls this before touching MuJoCo.
void install_mujoco_handlers();

/// Warnings MuJoCo raised so far in this process. Thread-safe; real-time safe.
std::uint64_t mujoco_warning_count() noexcept;

/// The text of the latest warning ("" if none). Not real-time safe (copies into a string).
std::string last_mujoco_warning();

}  // namespace cambio::sim
