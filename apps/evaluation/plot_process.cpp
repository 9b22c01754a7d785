#include "plot_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>

namespace cambio::app::detail {

namespace {

// The child's report, per figure in order: a header, then `size` bytes (the PNG when ok, else
// the error text).
struct Header {
  std::uint8_t ok = 0;
  std::uint64_t size = 0;
};

bool write_all(int fd, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, bytes, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    bytes += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

/// Reads exactly `size` bytes; false at the end of the pipe (the child ended) first.
bool read_all(int fd, void* data, std::size_t size) {
  auto* bytes = static_cast<std::uint8_t*>(data);
  while (size > 0) {
    const ssize_t n = ::read(fd, bytes, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    bytes += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

[[noreturn]] void draw_in_child(const std::vector<Figure>& figures, int fd) {
  for (const Figure& figure : figures) {
    Header header;
    std::vector<std::uint8_t> png;
    std::string error;
    try {
      png = draw_png(figure);
      header.ok = 1;
      header.size = png.size();
    } catch (const std::exception& failure) {
      error = failure.what();
      header.size = error.size();
    }
    if (!write_all(fd, &header, sizeof header) ||
        !write_all(fd, header.ok ? static_cast<const void*>(png.data()) : error.data(),
                   header.size)) {
      ::_exit(1);
    }
  }
  // _exit: the parent's atexit handlers and the leak checker are the parent's business.
  ::_exit(0);
}

std::string ended_how(int status) {
  if (WIFSIGNALED(status)) {
    const int signal_number = WTERMSIG(status);
    const char* name = sigabbrev_np(signal_number);
    return std::string("the plotting process was ended by SIG") + (name ? name : "?") + " (" +
           strsignal(signal_number) +
           "; out of memory or threads? its message is above) before drawing it";
  }
  // PLplot itself exits on an error it cannot return (out of memory among them).
  return "the plotting process exited with status " + std::to_string(WEXITSTATUS(status)) +
         " (its message is above) before drawing it";
}

}  // namespace

std::vector<DrawnFigure> draw_pngs_in_child(const std::vector<Figure>& figures) {
  std::vector<DrawnFigure> drawn(figures.size());
  for (std::size_t i = 0; i < figures.size(); ++i) drawn[i].file = figures[i].file;
  if (figures.empty()) return drawn;
  const auto fail_all_from = [&](std::size_t first, const std::string& why) {
    for (std::size_t i = first; i < drawn.size(); ++i) drawn[i].error = why;
  };

  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    fail_all_from(
        0, std::string("cannot make a pipe for the plotting process: ") + std::strerror(errno));
    return drawn;
  }
  const pid_t child = ::fork();
  if (child < 0) {
    const int error = errno;
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
    fail_all_from(0, std::string("cannot start the plotting process: ") + std::strerror(error));
    return drawn;
  }
  if (child == 0) {
    ::close(pipe_fds[0]);
    // A stop signal is the parent's to handle (it decides whether to hurry past the plots); the
    // run's handlers would only set flags in this copy of it.
    ::signal(SIGINT, SIG_IGN);
    ::signal(SIGTERM, SIG_IGN);
    ::signal(SIGHUP, SIG_IGN);
    draw_in_child(figures, pipe_fds[1]);
  }
  ::close(pipe_fds[1]);

  std::size_t received = 0;
  for (; received < figures.size(); ++received) {
    Header header;
    if (!read_all(pipe_fds[0], &header, sizeof header)) break;
    std::vector<std::uint8_t> payload(header.size);
    if (!read_all(pipe_fds[0], payload.data(), payload.size())) break;
    if (header.ok) {
      drawn[received].png = std::move(payload);
    } else {
      drawn[received].error.assign(payload.begin(), payload.end());
    }
  }
  ::close(pipe_fds[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (received < figures.size()) fail_all_from(received, ended_how(status));
  return drawn;
}

}  // namespace cambio::app::detail
