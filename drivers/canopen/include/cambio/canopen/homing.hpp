#pragma once

// CiA 402 homing (mode 6) as the master runs it at activate, before the joint is ever commanded
// in CSP or CSV (CiA 402-2 §12): over SDO, modes of operation 6, the drive enabled one
// transition at a time, controlword bit 4 raised to start, then the statusword's homing bits
// (cia402.hpp: 13 error, 12 attained, 10 target reached) followed until homing completed (12 and
// 10), a homing error (13), the drive's fault, its reboot (a boot-up) or the rig's timeout. The
// drive is then disabled (switch on disabled, where configure() left it) and put back in its
// cyclic mode; the joint loop enables it at its measured, now homed, position.
// Blocks and allocates: activate time only, never in a loop.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "cambio/canopen/bus_pump.hpp"
#include "cambio/canopen/can_rig.hpp"
#include "cambio/canopen/pdo_codec.hpp"

namespace cambio::canopen {

/// How one joint's homing went.
struct HomingRecord {
  std::string joint;
  int node_id = 0;
  int method = 0;
  /// From controlword bit 4 (start) to the statusword showing homing completed (or the failure).
  double duration_s = 0.0;
  /// Each statusword read while homing that differs from the one before, in order.
  std::vector<std::uint16_t> statuswords;
  /// The drive after homing: switch on disabled, its position in the homed frame.
  DriveFeedback feedback;
  /// Homed while the loop ran (a kHome request), not at activate.
  bool on_request = false;
};

/// Why homing did not complete.
enum class HomingFailure : std::uint8_t {
  kHomingError,    ///< Statusword bit 13.
  kTimeout,        ///< Not completed within the rig's timeout_s.
  kDriveFault,     ///< The drive went to fault (reaction active or fault).
  kDriveRebooted,  ///< A boot-up from the drive: it restarted and lost what it was doing.
  kNotEnabled,     ///< The drive did not reach operation enabled in homing mode.
  // Loop-side homing only (homing_sequencer.hpp):
  kNotDisabled,  ///< The drive did not reach switch on disabled (before or after homing).
  kSdoFailed,    ///< A mode change over SDO was refused or not answered.
  kStopped,      ///< The group held (a fault, loss or reboot elsewhere) or the bus went down.
};

/// "homing error", "homing timeout", ...
const char* to_string(HomingFailure failure);

/// Homing that did not complete. what(): "node 1 (joint 'pan'): homing error (statusword bit 13)
/// after 0.52 s, statusword 0x2637".
class HomingFailed : public std::runtime_error {
 public:
  HomingFailed(const std::string& message, HomingFailure failure, HomingRecord record)
      : std::runtime_error(message), failure_(failure), record_(std::move(record)) {}
  HomingFailure failure() const { return failure_; }
  const HomingRecord& record() const { return record_; }

 private:
  HomingFailure failure_;
  HomingRecord record_;
};

/// Homes `joint`'s drive at `node_id` with `homing`, polling its statusword every
/// `poll_period_s`; `operation_mode` is the cyclic mode to go back to. Takes over `pump`'s
/// other-frame handler (it watches for the node's boot-up). Throws HomingFailed, or SdoError
/// (naming node and object) when the drive stops answering or refuses a write.
HomingRecord home_drive(BusPump& pump, const std::string& joint, int node_id,
                        const HomingSettings& homing, hal::CommandMode operation_mode,
                        double sdo_timeout_s, double poll_period_s = 0.01);

}  // namespace cambio::canopen
