#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cambio/control/arm_command.hpp"
#include "cambio/control/gaze_command.hpp"
#include "cambio/hal/loop.hpp"
#include "cambio/hal/seqlock_channel.hpp"

namespace cambio::control {

/// The experiment runner's timeline: sends each scripted command on the gaze loop's command
/// channel, or the arms' for an arm entry, once the run has lasted its time, as a user at the
/// paper's console would type it.
/// Times count from the first update after activate(). Allocates only at construction.
class CommandScript final : public hal::Loop {
 public:
  struct Entry {
    double at_s = 0.0;  ///< Run time at which the command is sent (non-decreasing).
    GazeCommand command;
    bool to_arms = false;  ///< Send arm_command to the arms instead of `command`.
    ArmCommand arm_command;
  };

  /// Throws std::invalid_argument for times that are negative, not finite or out of order, or
  /// an arm entry without `arm_commands`.
  CommandScript(std::vector<Entry> entries, hal::SeqlockChannel<GazeCommand>& commands,
                hal::SeqlockChannel<ArmCommand>* arm_commands = nullptr);

  const std::string& name() const override { return name_; }
  void activate() override;
  hal::Status update(const hal::LoopTick& tick) noexcept override;

  /// Clock time of the first update (the run's time 0 for the script); 0 before it.
  std::int64_t start_ns() const { return start_ns_; }
  /// When each entry was sent (clock ns), -1 if not yet; in entry order.
  const std::vector<std::int64_t>& sent_ns() const { return sent_ns_; }
  const std::vector<Entry>& entries() const { return entries_; }

 private:
  std::string name_ = "script";
  std::vector<Entry> entries_;
  std::vector<std::int64_t> sent_ns_;
  hal::SeqlockChannel<GazeCommand>& commands_;
  hal::SeqlockChannel<ArmCommand>* arm_commands_;
  std::size_t next_ = 0;
  std::uint64_t sequence_ = 0;
  std::uint64_t arm_sequence_ = 0;
  std::int64_t start_ns_ = 0;
  bool started_ = false;
};

}  // namespace cambio::control
