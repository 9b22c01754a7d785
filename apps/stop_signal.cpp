#include "stop_signal.hpp"

#include <unistd.h>

#include <csignal>

namespace cambio::app {
namespace {

std::atomic<bool> g_stop_requested{false};
std::atomic<int> g_stop_signal{0};
std::atomic<bool> g_hurry{false};

// A robot stack's last act is to leave the drives safe: a later signal asks to hurry (skip what
// is optional), never to end the program before the quick stop and disable have run.
extern "C" void on_stop_signal(int signal_number) {
  if (g_stop_requested.exchange(true)) {
    g_hurry.store(true);
    return;
  }
  g_stop_signal.store(signal_number);
}

}  // namespace

const std::atomic<bool>& install_stop_signal_handlers() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    sigaction(signal_number, &action, nullptr);
  }
  return g_stop_requested;
}

bool stop_hurried() {
  return g_hurry.load();
}

int stop_signal_number() {
  return g_stop_signal.load();
}

int exit_status_for_signal(int signal_number) {
  if (signal_number == SIGHUP) return 128 + SIGTERM;
  return 128 + signal_number;
}

}  // namespace cambio::app
