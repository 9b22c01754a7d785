#pragma once

// CiA 402 homing (mode 6) while the joint loop runs: a console's `home`, or a drive that rebooted
// and lost its reference when the experiment asks it to home again. The same sequence as
// home_drive() (homing.hpp) runs at activate, but on the loop side: the controlword goes in the
// drive's RPDO each cycle and the statusword comes from its TPDO, so homing shares the bus with
// the running loop; only the two mode changes are SDO writes, one exchange in flight at a time.
//   1. controlword 0 until the drive is switch on disabled (whatever it was doing),
//   2. SDO 0x6060 = 6 (homing),
//   3. the CiA 402 transitions to operation enabled,
//   4. controlword bit 4 raised: homing runs; the statusword's bits 13 (error), 12 (attained) and
//      10 (target reached) followed to completion, a homing error, a fault, a reboot or the rig's
//      timeout_s,
//   5. controlword 0 until switch on disabled, then SDO 0x6060 back to the cyclic mode.
// The joint group enables the drive again afterwards, at its measured (now homed) position.
// No allocation, no lock, no blocking; it never sends itself: the group carries its pending SDO
// frame in the cycle's batched send and feeds it the node's SDO answers and statuswords.

#include <array>
#include <cstdint>
#include <span>

#include "cambio/canopen/cia402.hpp"
#include "cambio/canopen/homing.hpp"
#include "cambio/canopen/sdo_client.hpp"
#include "cambio/hal/can_bus.hpp"

namespace cambio::canopen {

/// Why a loop-side homing failed: fixed size, so the loop fills it without allocating and
/// another thread reads it through a SeqlockChannel.
struct HomingError {
  std::int32_t node_id = 0;  ///< 0: none failed.
  HomingFailure failure = HomingFailure::kHomingError;
  /// e.g. "node 1: homing method 17: homing error (statusword bit 13) after 0.412 s,
  /// statusword 0x2637". NUL-terminated.
  std::array<char, 192> text{};
};

class HomingSequencer {
 public:
  enum class State : std::uint8_t { kIdle, kRunning, kDone, kFailed };

  /// The most distinct statuswords a run keeps (the rest are counted, not kept).
  static constexpr std::size_t kMaxStatuswords = 24;

  /// Starts homing `node_id` with rig method `method` (already written to the drive at
  /// configure); `homing_timeout_ns` bounds step 4 (the rig's timeout_s), `step_timeout_ns`
  /// each other step (an SDO answer, a state transition). `cyclic_mode` is the mode to go back to.
  void start(int node_id, int method, std::int64_t homing_timeout_ns, std::int64_t step_timeout_ns,
             cia402::Mode cyclic_mode, std::int64_t now_ns);

  /// The controlword the drive's RPDO carries this cycle.
  std::uint16_t controlword() const { return controlword_; }
  /// The statusword of the drive's TPDO that answered the last SYNC (call only when it did).
  void on_statusword(std::uint16_t statusword, std::int64_t now_ns);
  /// An SDO response from the node (0x580 + node id).
  void on_sdo_frame(const hal::CanFrame& frame, std::int64_t now_ns);
  /// The node sent a boot-up: it restarted and lost what it was doing.
  void on_boot_up(std::int64_t now_ns);
  /// Checks the step and homing timeouts.
  void poll(std::int64_t now_ns);
  /// Ends a running homing as failed (`failure`, e.g. the group holds after a fault elsewhere);
  /// the drive is sent controlword 0 from then on.
  void stop(HomingFailure failure, std::int64_t now_ns);

  /// The SDO frame to send next, if any.
  bool has_pending() const { return pending_; }
  const hal::CanFrame& pending_frame() const { return pending_frame_; }
  /// The pending frame went out.
  void on_sent() { pending_ = false; }

  State state() const { return state_; }
  bool running() const { return state_ == State::kRunning; }
  int node_id() const { return client_.node_id(); }
  int method() const { return method_; }
  /// From controlword bit 4 to homing completed (or the failure); 0 before step 4.
  double duration_s() const { return duration_s_; }
  /// Each statusword seen from step 3 on that differs from the one before, in order.
  std::span<const std::uint16_t> statuswords() const {
    return std::span(statuswords_).first(statusword_count_);
  }
  /// Why it failed (valid once kFailed).
  const HomingError& error() const { return error_; }

 private:
  enum class Step : std::uint8_t {
    kDisabling,
    kModeHoming,
    kEnabling,
    kHoming,
    kStopping,
    kModeCyclic,
  };

  void enter(Step step, std::int64_t now_ns);
  void write_mode(cia402::Mode mode, std::int64_t now_ns);
  void keep(std::uint16_t statusword);
  void fail(HomingFailure failure, std::int64_t now_ns);
  void fail_sdo();

  SdoClient client_{0};
  int method_ = 0;
  cia402::Mode cyclic_mode_ = cia402::Mode::kCyclicSynchronousPosition;
  std::int64_t homing_timeout_ns_ = 0;
  std::int64_t step_timeout_ns_ = 0;
  State state_ = State::kIdle;
  Step step_ = Step::kDisabling;
  std::int64_t step_since_ns_ = 0;
  std::int64_t homing_since_ns_ = 0;
  /// TPDO answers since bit 4 went up: the first may predate the drive acting on it.
  int answers_since_start_ = 0;
  std::uint16_t controlword_ = cia402::kControlDisableVoltage;
  std::uint16_t last_statusword_ = 0;
  bool pending_ = false;
  hal::CanFrame pending_frame_{};
  std::array<std::uint8_t, 1> mode_byte_{};
  double duration_s_ = 0.0;
  std::array<std::uint16_t, kMaxStatuswords> statuswords_{};
  std::size_t statusword_count_ = 0;
  HomingError error_{};
};

}  // namespace cambio::canopen
