#include "console_input.hpp"

#include <iostream>

#include "bounded_line.hpp"

namespace cambio::app {

namespace {

constexpr const char* kPrompt = "cambio> ";

}  // namespace

std::optional<std::string> TerminalLines::try_pop(bool& eof) {
  std::lock_guard lock(mutex_);
  eof = eof_ && lines_.empty();
  if (lines_.empty()) return std::nullopt;
  std::string line = std::move(lines_.front());
  lines_.pop_front();
  return line;
}

void TerminalLines::ready() {
  std::lock_guard lock(mutex_);
  want_ = true;
  wanted_.notify_one();
}

bool TerminalLines::too_long() {
  std::lock_guard lock(mutex_);
  return too_long_;
}

void TerminalLines::read() {
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      wanted_.wait(lock, [this] { return want_; });
      want_ = false;
    }
    std::cout << kPrompt << std::flush;
    std::string line;
    const LineRead got = read_bounded_line(std::cin, line);
    std::lock_guard lock(mutex_);
    if (got != LineRead::kLine) {
      too_long_ = got == LineRead::kTooLong;
      eof_ = true;
      return;
    }
    lines_.push_back(std::move(line));
  }
}

std::optional<std::string> LineSource::next(bool& eof) {
  if (terminal_) {
    std::optional<std::string> line = terminal_->try_pop(eof);
    if (eof && terminal_->too_long()) report_too_long();
    return line;
  }
  std::string line;
  if (script_) {
    eof = static_cast<std::size_t>(line_number_) >= script_->size();
    if (eof) return std::nullopt;
    line = (*script_)[static_cast<std::size_t>(line_number_++)];
    std::cout << kPrompt << line << "\n";
    return line;
  }
  const LineRead got = read_bounded_line(std::cin, line);
  ++line_number_;
  eof = got != LineRead::kLine;
  if (got == LineRead::kTooLong) report_too_long();
  if (eof) return std::nullopt;
  std::cout << kPrompt << line << "\n";  // The transcript shows what was carried out.
  return line;
}

void LineSource::report_too_long() {
  if (input_refused_) return;
  input_refused_ = true;
  std::cerr << "cambio console: input line " << (terminal_ ? 0 : line_number_) << " is longer than "
            << kMaxInputLineChars
            << " characters: not console commands; stopping the robot and the session\n";
}

}  // namespace cambio::app
