#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "cambio/canopen/cia402.hpp"
#include "cambio/canopen/protocol.hpp"
#include "cambio/hal/can_bus.hpp"
#include "cambio/hal/drive_state.hpp"
#include "cambio/sim/servo_model.hpp"
#include "cambio/virtual_rig/fault_injection.hpp"
#include "cambio/virtual_rig/object_dictionary.hpp"
#include "cambio/virtual_rig/sdo_server.hpp"

namespace cambio::virtual_rig {

/// What one emulated drive is: its node, its joint's servo (the sim's model, same noise) and the
/// units on the bus.
struct EmulatedDriveConfig {
  int node_id = 1;
  sim::ServoParams servo;  ///< The joint's servo model (step, limits, noise, dead time, encoder).
  std::uint64_t seed = 0;  ///< The servo's noise seed.
  double initial_position_rad = 0.0;
  double gear_ratio = 1.0;                     ///< Motor turns per joint turn.
  std::int64_t encoder_counts_per_rev = 4096;  ///< Motor encoder counts per motor turn.
  /// 0x6065's default; 0 = following error monitoring off (0xFFFFFFFF, as CiA 402 says).
  double following_error_window_rad = 0.0;
  double position_window_rad = 0.001;  ///< 0x6067's default: "target reached" band.
  double heartbeat_period_s = 0.1;     ///< 0x1017's default (ms on the bus); 0 = none.
  hal::CommandMode mode = hal::CommandMode::kPosition;  ///< 0x6060's default (CSP or CSV).
  double rated_torque_nm = 1.0;  ///< 0x6076 (the unit of 0x6077 and 0x60B2: 1/1000 of it).
  /// Homing's limit switch, in the joint's angle (the rig's can.virtual_drive.home_switch): for
  /// method 17 the negative limit switch, active at and below it; for 18 the positive one,
  /// active at and above it. None: no switch is wired, a search ends at the joint's limit with a
  /// homing error.
  std::optional<double> home_switch_rad;
  /// One of the encoder's index pulses, in the joint's angle; they repeat every motor turn
  /// (2 pi / gear_ratio of joint angle). The rig's can.virtual_drive.index_pulse (default 0).
  double index_pulse_rad = 0.0;
};

/// Counters of what the drive saw and did, for tests and the command's report.
struct EmulatedDriveCounters {
  std::uint64_t syncs = 0;
  std::uint64_t rpdos = 0;
  std::uint64_t tpdos_sent = 0;
  std::uint64_t tpdos_dropped = 0;  ///< By fault injection.
  std::uint64_t tpdos_late = 0;     ///< By fault injection.
  std::uint64_t emergencies = 0;
  std::uint64_t heartbeats = 0;
  std::uint64_t malformed_frames = 0;  ///< Wrong length NMT/SYNC/RPDO/SDO: ignored.
  std::uint64_t send_failures = 0;     ///< The bus refused a frame (queue full, bus off).
};

/// One CiA 402 servo drive on a CAN bus, as CiA 301 and CiA 402 specify it, backed by the sim's
/// servo model:
/// - NMT slave: boot-up message at power on and after reset node / reset communication, then
///   pre-operational; start, stop, enter pre-operational. SDO in pre-operational and
///   operational, PDOs in operational only, only NMT and heartbeat in stopped.
/// - Heartbeat producer every 0x1017 ms (0 = off); SYNC consumer on 0x1005's COB-ID.
/// - PDOs: 4 RPDOs and 4 TPDOs whose communication (0x1400/0x1800) and mapping (0x1600/0x1A00)
///   objects follow CiA 301: mapping writable only while the PDO's COB-ID is invalid (bit 31) and
///   its count (sub 0) is 0; mapped objects must exist, be PDO-mappable with the right length and
///   fit 8 bytes. Synchronous RPDOs (type 0..240) take effect on the next SYNC, event RPDOs
///   (254, 255) at once; TPDOs are synchronous (type 1..240: every n-th SYNC; 0: on SYNC when
///   the data changed). Remote requests are not answered (no RTR).
/// - On SYNC: the servo model runs up to the SYNC's time, the actual values are sampled and the
///   TPDOs sent, then the targets received since the last SYNC are latched for the next cycle.
/// - Homing (mode 6, emulated_drive_homing.cpp): methods 17/18 (limit switch), 33/34 (index
///   pulse), 35/37 (current position); any other 0x6098 value is refused with an SDO abort.
/// - CiA 402 state machine on the controlword; modes 8 (CSP) and 9 (CSV); enable at the measured
///   position (no jump), quick stop on the deceleration ramp (then holds: quick stop option 6),
///   following error (|demand - actual| > 0x6065 -> fault, EMCY 0x8611); EMCY on every fault and
///   EMCY 0x0000 on fault reset.
/// Not thread-safe: one thread (the bus's) calls everything. After construction nothing
/// allocates.
class EmulatedDrive final : private SdoTarget {
 public:
  /// CiA 301's predefined connection set: four RPDOs (0x200/0x300/0x400/0x500 + node id) and
  /// four TPDOs (0x180/0x280/0x380/0x480 + node id), each with kMaxMappedObjects entries.
  static constexpr int kPdoCount = 4;
  static constexpr std::size_t kMaxMappedObjects = 8;
  static constexpr std::size_t kMaxScheduledFaults = 16;
  static constexpr std::size_t kMaxLateFrames = 16;

  /// Builds the object dictionary with its defaults. `bus` outlives the drive. Throws
  /// std::invalid_argument for a node id outside 1..127 or non-positive units.
  EmulatedDrive(EmulatedDriveConfig config, hal::CanBus& bus);

  /// Power on (transitions 0 and 1): the boot-up message, pre-operational, switch on disabled.
  void power_on(std::int64_t now_ns) noexcept;
  /// Handles one frame received from the bus at `now_ns`.
  void handle(const hal::CanFrame& frame, std::int64_t now_ns) noexcept;
  /// Time-driven work due at `now_ns`: the servo, heartbeat, late TPDOs, scheduled faults.
  void poll(std::int64_t now_ns) noexcept;
  /// When poll() next has something to do (heartbeat, late TPDO, scheduled fault).
  std::int64_t next_event_ns() const noexcept;

  /// Schedules a fault at fault.at_s after power on. Returns false when it is not for this node
  /// or the schedule is full (kMaxScheduledFaults).
  bool schedule(const FaultInjection& fault) noexcept;

  int node_id() const { return config_.node_id; }
  canopen::NmtState nmt_state() const { return nmt_state_; }
  hal::DriveState drive_state() const { return drive_state_; }
  const sim::ServoModel& servo() const { return servo_; }
  const ObjectDictionary& dictionary() const { return dictionary_; }
  const EmulatedDriveCounters& counters() const { return counters_; }
  const canopen::cia402::Units& units() const { return units_; }
  const EmulatedDriveConfig& config() const { return config_; }

 private:
  struct MappedEntry {
    ObjectEntry* entry = nullptr;
    std::size_t bytes = 0;
  };
  struct Pdo {
    std::array<MappedEntry, kMaxMappedObjects> entries{};
    std::size_t count = 0;
    std::size_t bytes = 0;
    bool valid = false;
    std::uint32_t cob_id = 0;
    std::uint8_t transmission_type = 0;
    // RPDO: data received, waiting for the next SYNC.
    std::array<std::uint8_t, 8> pending{};
    bool has_pending = false;
    // TPDO: SYNCs since the last transmission, last data sent (transmission type 0).
    int sync_count = 0;
    std::array<std::uint8_t, 8> last_sent{};
    bool sent_once = false;
  };
  struct LateFrame {
    hal::CanFrame frame;
    std::int64_t due_ns = 0;
  };
  struct ScheduledFault {
    FaultInjection fault;
    bool done = false;
  };

  // SdoTarget.
  std::uint32_t sdo_read(canopen::ObjectAddress address, std::span<std::uint8_t> out,
                         std::size_t& size) override;
  std::uint32_t sdo_write(canopen::ObjectAddress address,
                          std::span<const std::uint8_t> data) override;
  std::size_t sdo_size(canopen::ObjectAddress address) const override;

  void build_dictionary();  ///< The steps below, then finalise and find_live_objects().
  void add_communication_objects();
  void add_pdo_objects();
  void add_cia402_objects();
  void find_live_objects();
  void boot(std::int64_t now_ns) noexcept;
  void handle_nmt(const hal::CanFrame& frame, std::int64_t now_ns) noexcept;
  void handle_sync(std::int64_t now_ns) noexcept;
  void handle_rpdo(int pdo, const hal::CanFrame& frame) noexcept;
  std::uint32_t check_pdo_write(canopen::ObjectAddress address,
                                std::span<const std::uint8_t> data) const noexcept;
  std::uint32_t check_mapping(bool receive, std::uint32_t entry) const noexcept;
  void rebuild_pdos() noexcept;
  void apply_rpdo(const Pdo& pdo, std::span<const std::uint8_t> data) noexcept;
  void send_tpdos(std::int64_t now_ns) noexcept;

  // Homing (emulated_drive_homing.cpp).
  enum class HomingPhase : std::uint8_t {
    kIdle,      ///< Not started, or interrupted (bit 4 low, mode or state left).
    kSearch,    ///< At the switch speed towards the limit switch.
    kEdge,      ///< At the zero speed: off the switch (17/18), or to an index pulse (33/34).
    kToHome,    ///< Home found (attained): moving back onto the home position.
    kAttained,  ///< Standing at the home position: homing completed.
    kError,     ///< The joint's limit was reached without finding the switch.
  };
  static bool homing_method_supported(std::int8_t method) noexcept;
  void start_homing() noexcept;
  void step_homing() noexcept;
  void home_found(double home_rad) noexcept;
  std::uint16_t homing_status_bits() const noexcept;
  /// The drive's position frame: after homing its zero is origin_rad_ of the joint's angle.
  double to_drive_rad(double joint_rad) const { return joint_rad - origin_rad_; }

  void advance_servo(std::int64_t now_ns) noexcept;
  void on_controlword(std::uint16_t controlword) noexcept;
  void enter(hal::DriveState state) noexcept;
  void raise_fault(std::uint16_t error_code, std::uint8_t error_register_bits) noexcept;
  void latch_targets() noexcept;
  void update_actual_values() noexcept;
  void send_emergency(std::uint16_t error_code) noexcept;
  void send(const hal::CanFrame& frame) noexcept;
  void run_faults(std::int64_t now_ns) noexcept;
  /// When `fault` is due on this drive (INT64_MAX while an after-enable fault waits for enable).
  std::int64_t due_ns(const FaultInjection& fault) const noexcept;

  EmulatedDriveConfig config_;
  hal::CanBus& bus_;
  canopen::cia402::Units units_;
  ObjectDictionary dictionary_;
  SdoServer sdo_;
  sim::ServoModel servo_;
  std::int64_t step_ns_ = 1'000'000;

  canopen::NmtState nmt_state_ = canopen::NmtState::kBootUp;
  hal::DriveState drive_state_ = hal::DriveState::kNotReadyToSwitchOn;
  bool powered_ = false;
  std::int64_t power_on_ns_ = 0;
  std::int64_t first_enabled_ns_ = -1;  ///< When the drive first reached operation enabled.
  std::int64_t now_ns_ = 0;
  std::int64_t servo_time_ns_ = 0;
  std::int64_t next_heartbeat_ns_ = 0;
  std::uint16_t previous_controlword_ = 0;
  double demand_rad_ = 0.0;  ///< CSP: the latched target (position demand).
  /// A target was written since the drive was enabled (an older one is never executed).
  bool targets_written_ = false;
  bool following_error_ = false;
  bool heartbeat_stopped_ = false;
  int error_passive_syncs_left_ = 0;
  int tpdos_to_drop_ = 0;
  int tpdos_to_delay_ = 0;
  std::int64_t tpdo_delay_ns_ = 0;

  HomingPhase homing_phase_ = HomingPhase::kIdle;
  double homing_direction_ = 0.0;  ///< -1 or +1: where the search goes.
  double home_rad_ = 0.0;          ///< The home position found, in the joint's angle.
  double homing_last_rad_ = 0.0;   ///< The joint's angle at the previous servo step.
  double origin_rad_ = 0.0;        ///< The drive's zero in the joint's angle (0 until homed).

  std::array<Pdo, kPdoCount> rpdos_{};
  std::array<Pdo, kPdoCount> tpdos_{};
  std::array<LateFrame, kMaxLateFrames> late_{};
  std::size_t late_count_ = 0;
  std::array<ScheduledFault, kMaxScheduledFaults> faults_{};
  std::size_t fault_count_ = 0;
  EmulatedDriveCounters counters_;

  // Entries the loop side touches every cycle, resolved once.
  ObjectEntry* controlword_ = nullptr;
  ObjectEntry* statusword_ = nullptr;
  ObjectEntry* error_register_ = nullptr;
  ObjectEntry* error_code_ = nullptr;
  ObjectEntry* mode_ = nullptr;
  ObjectEntry* mode_display_ = nullptr;
  ObjectEntry* position_actual_ = nullptr;
  ObjectEntry* position_demand_ = nullptr;
  ObjectEntry* velocity_actual_ = nullptr;
  ObjectEntry* torque_actual_ = nullptr;
  ObjectEntry* target_position_ = nullptr;
  ObjectEntry* target_velocity_ = nullptr;
  ObjectEntry* velocity_offset_ = nullptr;
  ObjectEntry* torque_offset_ = nullptr;
  ObjectEntry* following_window_ = nullptr;
  ObjectEntry* position_window_ = nullptr;
  ObjectEntry* heartbeat_time_ = nullptr;
  ObjectEntry* sync_cob_id_ = nullptr;
  ObjectEntry* min_position_ = nullptr;
  ObjectEntry* max_position_ = nullptr;
  ObjectEntry* max_velocity_ = nullptr;
  ObjectEntry* home_offset_ = nullptr;
  ObjectEntry* homing_method_ = nullptr;
  ObjectEntry* homing_switch_speed_ = nullptr;
  ObjectEntry* homing_zero_speed_ = nullptr;
};

}  // namespace cambio::virtual_rig
