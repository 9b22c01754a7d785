#pragma once

// Where `cambio console`'s lines come from: a terminal, read by a thread of its own so the robot
// keeps running while the user types, or a pipe or file, read a line at a time when the previous
// one is done (a script is deterministic). Lines are bounded (bounded_line.hpp): a longer one
// ends the session.

#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace cambio::app {

/// Lines typed at a terminal, read by a thread of their own so the robot keeps running (and
/// time passes) while the user thinks.
class TerminalLines {
 public:
  TerminalLines() : reader_([this] { read(); }) {}
  ~TerminalLines() { reader_.detach(); }  // It may be blocked in getline: leave it be.
  TerminalLines(const TerminalLines&) = delete;
  TerminalLines& operator=(const TerminalLines&) = delete;

  /// The next line if one was typed; nullopt otherwise. `eof` is set once input has ended.
  std::optional<std::string> try_pop(bool& eof);
  /// Asks for the next line (prints the prompt) once the last one has been carried out.
  void ready();
  /// Input ended on a line longer than kMaxInputLineChars.
  bool too_long();

 private:
  void read();

  std::mutex mutex_;
  std::condition_variable wanted_;
  bool want_ = true;
  bool eof_ = false;
  bool too_long_ = false;
  std::deque<std::string> lines_;
  std::thread reader_;  // Last: it starts reading once everything it uses is made.
};

/// Where the console's lines come from: a terminal (the run goes on while the user types) or a
/// pipe or file (read when the previous line is done: a script is deterministic).
class LineSource {
 public:
  explicit LineSource(bool interactive) {
    if (interactive) terminal_.emplace();
  }
  /// The lines of a script a command made (calibrate capture), carried out as piped ones.
  explicit LineSource(std::vector<std::string> script) : script_(std::move(script)) {}
  bool interactive() const { return terminal_.has_value(); }
  /// nullopt with `eof` false: nothing typed yet (terminal only).
  std::optional<std::string> next(bool& eof);
  void done_with_line() {
    if (terminal_) terminal_->ready();
  }
  /// Input was refused (a line too long): the session ends there, and the command exits 2.
  bool input_refused() const { return input_refused_; }

 private:
  void report_too_long();

  std::optional<TerminalLines> terminal_;
  std::optional<std::vector<std::string>> script_;
  int line_number_ = 0;
  bool input_refused_ = false;
};

}  // namespace cambio::app
