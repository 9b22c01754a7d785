// `cambio`: the command-line front end. Dispatches to one subcommand per file.
#include <unistd.h>
#include <array>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "argument_parser.hpp"
#include "cambio/sim/address_space_limit.hpp"
#include "command.hpp"
#include "config_errors.hpp"
#include "output_directory.hpp"

namespace {

void print_usage(std::ostream& out) {
  out << "usage: cambio <command> [options]\n\nCâmbio: real-time control stack for active-vision "
         "robots.\n\ncommands:\n";
  for (const auto& command : cambio::app::all_commands()) {
    out << "  " << command.name
        << std::string(20 - std::min<std::size_t>(19, command.name.size()), ' ') << command.summary
        << "\n";
  }
  out << "\n'cambio <command> --help' describes a command.\n"
         "\nexit status:\n"
         "  0    success\n"
         "  1    the run finished but an experiment's goal failed\n"
         "  2    bad input: arguments, config, input files or images, an unusable --out\n"
         "  3    a device fault (drive or bus) stopped the run\n"
         "  130  stopped by SIGINT (Ctrl-C); 143 by SIGTERM or SIGHUP\n"
         "  where several apply: a signal over a device fault over a failed goal\n"
         "  out of memory is said as such (exit 1; under an address-space limit, with the limit,\n"
         "  a crash inside a library included)\n";
}

/// Standard output is where --json and check-config answer: a failed write (a full disk, a
/// closed pipe) is an error, never exit 0.
int check_standard_output(const std::string& command, int status) {
  std::cout.flush();
  const bool failed = !std::cout.good() || std::fflush(stdout) != 0 || std::ferror(stdout) != 0;
  if (!failed) return status;
  std::cerr << "cambio " << command
            << ": cannot write to standard output: " << std::strerror(errno != 0 ? errno : EIO)
            << "\n";
  return status == cambio::app::kExitOk ? cambio::app::kExitBadInput : status;
}

// Under an address-space limit (ulimit -v) Mesa's llvmpipe, LLVM and GLib do not all check their
// allocations: at the same limit a run may abort ("Unable to allocate section memory"), trap
// (GLib creating a thread) or segfault inside the driver, from one run to the next. Such a crash
// is memory running out and is said as such, with exit 1 like every other out-of-memory; it can
// only come from a library (our own code under the sanitizers is checked without limits). The
// messages are made before anything can fail and written from the handler with write(2) and
// _exit(2) alone (async-signal-safe). Without a limit a crash stays a crash.
struct CrashUnderALimit {
  int signal_number;
  const char* name;
  std::string message;
};
std::array<CrashUnderALimit, 4> g_crashes_under_a_limit{{{SIGABRT, "SIGABRT", ""},
                                                         {SIGSEGV, "SIGSEGV", ""},
                                                         {SIGBUS, "SIGBUS", ""},
                                                         {SIGTRAP, "SIGTRAP", ""}}};

extern "C" void say_crash_under_a_memory_limit(int signal_number) {
  for (const CrashUnderALimit& crash : g_crashes_under_a_limit) {
    if (crash.signal_number != signal_number) continue;
    [[maybe_unused]] const ssize_t ignored =
        ::write(STDERR_FILENO, crash.message.data(), crash.message.size());
  }
  ::_exit(cambio::app::kExitFailure);
}

void install_crash_note_under_a_memory_limit() {
  const std::string note = cambio::sim::address_space_limit_note();
  if (note.empty()) return;
  for (CrashUnderALimit& crash : g_crashes_under_a_limit) {
    crash.message = std::string("cambio: out of memory: ") + crash.name +
                    " inside a library (Mesa, LLVM or GLib)" + note + "\n";
    struct sigaction action {};
    action.sa_handler = say_crash_under_a_memory_limit;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;
    sigaction(crash.signal_number, &action, nullptr);
  }
}

}  // namespace

int main(int argc, char** argv) {
  install_crash_note_under_a_memory_limit();
  // A reader that went away (`cambio ... | head`) is a failed write, checked like a full disk
  // (exit 2 with the reason), not a silent death by SIGPIPE that skips a console's clean stop.
  std::signal(SIGPIPE, SIG_IGN);
  // The same for a file-size limit (ulimit -f): the write that crosses it fails with EFBIG and
  // is reported, instead of SIGXFSZ killing the program with no message and the drives enabled.
  std::signal(SIGXFSZ, SIG_IGN);
  if (argc < 2) {
    print_usage(std::cerr);
    return cambio::app::kExitBadInput;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    print_usage(std::cout);
    return check_standard_output("--help", cambio::app::kExitOk);
  }
  const std::vector<std::string> args(argv + 2, argv + argc);
  for (const auto& command : cambio::app::all_commands()) {
    if (command.name != name) continue;
    try {
      errno = 0;
      return check_standard_output(name, command.run(args));
    } catch (const cambio::app::UsageError& error) {
      std::cerr << "cambio " << error.what() << "\n";
      return cambio::app::kExitBadInput;
    } catch (const cambio::app::OutputError& error) {
      std::cerr << "cambio " << name << ": " << error.what() << "\n";
      return cambio::app::kExitBadInput;
    } catch (const cambio::config::ConfigError& error) {
      // Configuration found before a command's own loading (CAMBIO_CONFIG_DIR, shipped defaults).
      cambio::app::report_config_error(error);
      return cambio::app::kExitBadInput;
    } catch (const cambio::sim::OutOfMemory& error) {
      std::cerr << "cambio " << name << ": out of memory: " << error.what() << "\n";
      return cambio::app::kExitFailure;
    } catch (const std::bad_alloc&) {
      std::cerr << "cambio " << name << ": out of memory" << cambio::sim::address_space_limit_note()
                << "\n";
      return cambio::app::kExitFailure;
    } catch (const std::exception& error) {
      // Under an address-space limit a library's failure (a thread that cannot start) is most
      // likely memory running out: the limit is named.
      std::cerr << "cambio " << name << ": error: " << error.what()
                << cambio::sim::address_space_limit_note() << "\n";
      return cambio::app::kExitFailure;
    }
  }
  std::cerr << "cambio: unknown command '" << name << "'\n\n";
  print_usage(std::cerr);
  return cambio::app::kExitBadInput;
}
