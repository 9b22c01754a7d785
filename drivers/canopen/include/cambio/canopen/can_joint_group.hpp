#pragma once

// A joint group of CiA 402 drives on one CAN bus (hal::JointGroup). One joint-loop cycle:
//   read()   drain the bus: the TPDOs that answered the previous SYNC (per-joint stamps from the
//            frames), heartbeats, boot-ups, EMCYs; malformed or unexpected frames are counted
//            and ignored; a drive silent for settings.stale_after_missed_syncs SYNCs is stale,
//            one whose heartbeat missed 3 periods is lost (latched kJointCommLost)
//   write()  clamp, then controlword + target per drive into the RPDOs
//   sync()   every RPDO then SYNC, with one send_batch
// After a fault, a loss or a reboot anywhere in the group, or the bus going bus-off or down, no
// motion command goes out for the group: enabled drives are quick-stopped at their measured
// positions until a fault reset. A fault reset also clears a bus fault once the bus carries frames
// again (after the kernel's restart-ms), and replays the configuration of drives that rebooted
// (node_reconfiguration.hpp), one SDO exchange per cycle; such a drive is enabled again only by a
// later enable request, at its measured position. A joint whose rig sets homing is kept disabled
// (controlword 0, target its measured position) until it has homed (set_homed), and again once
// its drive reboots: its reference is gone. A kHome request homes joints again while the loop
// runs (homing_sequencer.hpp), one drive at a time, never beside a reconfiguration; the joint
// reports kJointHoming and is not driven until homing ends and it is enabled at its new position.
// The group is the bus's SYNC producer: one CAN group per bus.
// read/write/sync/request: no allocation, no lock, no blocking, one send system call per cycle.

#include <array>
#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include "cambio/canopen/cia402_drive.hpp"
#include "cambio/canopen/emcy_consumer.hpp"
#include "cambio/canopen/homing.hpp"
#include "cambio/canopen/homing_sequencer.hpp"
#include "cambio/canopen/nmt_master.hpp"
#include "cambio/canopen/node_reconfiguration.hpp"
#include "cambio/canopen/pdo_layout.hpp"
#include "cambio/hal/can_bus.hpp"
#include "cambio/hal/clock.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/hal/joint_group.hpp"
#include "cambio/hal/seqlock_channel.hpp"

namespace cambio::canopen {

/// What went wrong on a group's bus, for reporting. Counts since construction.
struct CanGroupCounters {
  std::uint64_t syncs_sent = 0;
  std::uint64_t tpdos_received = 0;
  std::uint64_t missed_sync_answers = 0;  ///< Drive-cycles with no TPDO1 after a SYNC.
  std::uint64_t late_tpdos = 0;           ///< TPDOs that arrived after the next SYNC went out.
  std::uint64_t malformed_frames = 0;     ///< Wrong length or flags for their COB-ID.
  std::uint64_t unexpected_frames = 0;    ///< COB-IDs this group has nothing to do with.
  std::uint64_t tx_queue_full = 0;        ///< Frames a full transmit queue did not take.
  std::uint64_t emergencies = 0;
  std::uint64_t error_frames = 0;
  std::uint64_t boot_ups = 0;
  std::uint64_t bus_faults = 0;                ///< Times the bus was found bus-off or down.
  std::uint64_t reconfigurations = 0;          ///< Rebooted drives configured again, verified.
  std::uint64_t reconfiguration_failures = 0;  ///< Abort, timeout or read-back mismatch.
  /// Cycles whose read() stopped at max_frames_per_read(): the frames still queued wait for the
  /// next cycle (a flooded bus cannot hold the joint loop).
  std::uint64_t receive_cap_reached = 0;
  /// Every frame this group sent and took off its bus (one group per bus: the bus's whole
  /// traffic), and their bits on the wire in the worst case (can_frame_worst_case_bits): the
  /// bus load is the bits' growth per second over the bitrate.
  std::uint64_t frames_sent = 0;
  std::uint64_t frames_received = 0;
  std::uint64_t bus_bits = 0;
  std::uint64_t homings = 0;          ///< Loop-side homings that completed (kHome requests).
  std::uint64_t homing_failures = 0;  ///< Loop-side homings that failed (last_homing_error()).
};

class CanJointGroup final : public hal::JointGroup {
 public:
  /// `drives[k]` is the drive of `info.joints[k]`; `settings` the group's CANopen settings;
  /// `rate_hz` its SYNC rate. `bus` and `clock` outlive the group. Throws std::invalid_argument
  /// on bad node ids or units.
  CanJointGroup(hal::JointGroupInfo info, CanGroupSettings settings,
                std::vector<JointDriveInfo> drives, double rate_hz, hal::CanBus& bus,
                const hal::Clock& clock);

  const hal::JointGroupInfo& info() const override { return info_; }
  const CanGroupSettings& settings() const { return settings_; }
  hal::Status read(std::span<hal::JointState> out, std::int64_t& stamp_ns) override;
  hal::Status write(std::span<const hal::JointCommand> commands) override;
  hal::Status request(hal::DriveRequest request, int joint = kAllJoints) override;
  hal::Status sync() override;

  /// The most frames one read() takes off the bus: every drive's answers to a SYNC and its
  /// heartbeat, EMCY and SDO frames eight times over, and room for NMT and error frames.
  std::size_t max_frames_per_read() const { return 8 * slots_.size() + 32; }

  /// Thread-safe snapshot of the counters.
  CanGroupCounters counters() const;

  // Lifecycle, called by the backend outside the loop.
  const PdoLayout& layout() const { return layout_; }
  double rate_hz() const { return rate_hz_; }
  /// The bus's (nominal) bitrate, for its load; 0: unknown. Set by the backend before the loops.
  void set_bus_bitrate(std::int64_t bitrate_bit_s) { bus_bitrate_bit_s_ = bitrate_bit_s; }
  std::int64_t bus_bitrate_bit_s() const { return bus_bitrate_bit_s_; }
  hal::CanBus& bus() { return bus_; }
  std::size_t size() const { return slots_.size(); }
  const Cia402Drive& drive(std::size_t joint) const { return slots_[joint].drive; }
  /// The drive's state read over SDO at configure time, so the first read() is real.
  void seed_feedback(std::size_t joint, const DriveFeedback& feedback, std::int64_t stamp_ns);
  /// The motor's rated torque (0x6076, N m) for effort feed-forward and feedback
  /// (torque_units.hpp); 0 = unknown: effort is neither sent nor reported.
  void set_rated_torque(std::size_t joint, double rated_torque_nm);
  /// The SDO writes configure() made on the joint's drive (drive parameters, then PDO
  /// configuration), replayed when the drive reboots. Without them a rebooted drive stays lost.
  void set_configuration(std::size_t joint, std::span<const ObjectWrite> writes);
  /// Why the last loop-side reconfiguration failed (node_id 0: none failed). Thread-safe.
  ReconfigurationError last_reconfiguration_error() const;
  /// The joint's drive homed at activate (homing.hpp): from now on it may be enabled and driven.
  /// Outside the loop. A joint whose rig sets homing and that has not homed, or whose drive
  /// rebooted since (its reference is gone), is kept disabled and never commanded in CSP or CSV.
  void set_homed(std::size_t joint, HomingRecord record);
  /// Whether the joint must home and has (always true for a joint that does not home). Loop
  /// thread, or before the loops start.
  bool homed(std::size_t joint) const { return !slots_[joint].must_home || slots_[joint].homed; }
  /// How each joint's homing went (at activate, then on kHome requests, in the order they
  /// completed; loop-side homings beyond kMaxLoopHomings are counted, not kept). Read it once
  /// the loops stopped.
  std::vector<HomingRecord> homing_records() const;
  static constexpr std::size_t kMaxLoopHomings = 32;
  /// Why the last loop-side homing failed (node_id 0: none failed). Thread-safe.
  HomingError last_homing_error() const;
  /// The joint's drive is homing on the loop side (loop thread).
  bool homing(std::size_t joint) const { return homing_joint_ == static_cast<int>(joint); }
  /// Starts watching heartbeats and SYNC answers (activate()).
  void arm(std::int64_t now_ns);
  /// Drives that sent a boot-up since arm(): their configuration is gone until replayed.
  bool needs_reconfiguration(std::size_t joint) const { return slots_[joint].heartbeat.rebooted(); }
  /// The joint's drive is being configured again (loop thread).
  bool reconfiguring(std::size_t joint) const { return reconfiguring_ == static_cast<int>(joint); }
  /// The bus was found bus-off or down and no fault reset has cleared it yet (loop thread).
  bool bus_fault() const { return bus_fault_; }
  /// One RPDO1 per drive carrying `controlword` and the measured position, then SYNC, into
  /// `out` (size >= size() + 1); returns the count. For deactivate(): quick stop, disable.
  std::size_t shutdown_frames(std::uint16_t controlword, std::span<hal::CanFrame> out) const;

 private:
  struct Slot {
    Cia402Drive drive;
    HeartbeatConsumer heartbeat;
    EmergencyRecord emergency;
    hal::JointCommand command{};
    std::vector<ReconfigurationStep> configuration;  ///< Empty: cannot be reconfigured.
    bool reconfiguration_requested = false;
    std::int64_t stamp_ns = 0;
    int missed_syncs = 0;
    bool answered = false;  ///< A TPDO1 since the last SYNC.
    std::uint32_t clamped_bits = 0;
    bool must_home = false;  ///< The rig sets homing for this joint.
    bool homed = false;      ///< Homed since the drive last booted.
    bool home_requested = false;
    HomingSettings homing{};  ///< The rig's homing (must_home).
  };
  /// A loop-side homing that completed, kept without allocating.
  struct LoopHoming {
    std::size_t joint = 0;
    double duration_s = 0.0;
    std::array<std::uint16_t, HomingSequencer::kMaxStatuswords> statuswords{};
    std::size_t statusword_count = 0;
    DriveFeedback feedback{};
  };

  void dispatch(const hal::CanFrame& frame, std::int64_t now_ns);
  void on_tpdo(Slot& slot, int pdo, const hal::CanFrame& frame, std::int64_t stamp_ns);
  bool faulted_or_lost(const Slot& slot) const;
  void check_bus();
  void run_reconfiguration(std::int64_t now_ns);
  void run_homing(std::int64_t now_ns);
  /// The SDO frame of a reconfiguration or a homing to carry after SYNC, if any (never both).
  const hal::CanFrame* extra_frame() const;
  void build_rpdos(bool use_commands);
  static void bump(std::atomic<std::uint64_t>& counter, std::uint64_t by = 1) {
    counter.store(counter.load(std::memory_order_relaxed) + by, std::memory_order_relaxed);
  }

  hal::JointGroupInfo info_;
  CanGroupSettings settings_;
  double rate_hz_;
  std::int64_t bus_bitrate_bit_s_ = 0;
  hal::CanBus& bus_;
  const hal::Clock& clock_;
  PdoLayout layout_;
  std::vector<Slot> slots_;
  std::array<std::int16_t, kMaxNodeId + 1> slot_of_node_{};  ///< -1: not in the group.
  std::vector<hal::CanFrame> tx_;                            ///< RPDOs of every drive, then SYNC.
  std::size_t tx_count_ = 0;
  bool written_ = false;
  bool hold_latched_ = false;
  bool reset_pending_ = false;
  bool sync_to_check_ = false;  ///< A SYNC went out whose answers read() has not checked.
  std::int64_t last_sync_ns_ = 0;
  std::int64_t stale_after_syncs_ = 3;
  bool bus_fault_ = false;
  NodeReconfiguration reconfiguration_;
  int reconfiguring_ = -1;  ///< The joint being reconfigured, or -1.
  std::int64_t sdo_timeout_ns_ = 0;
  hal::SeqlockChannel<ReconfigurationError> last_error_;
  std::vector<HomingRecord> homing_records_;  ///< At activate (set_homed).
  HomingSequencer homing_;
  int homing_joint_ = -1;  ///< The joint homing on the loop side, or -1.
  std::array<LoopHoming, kMaxLoopHomings> loop_homings_{};
  std::size_t loop_homing_count_ = 0;
  hal::SeqlockChannel<HomingError> last_homing_error_;

  struct AtomicCounters {
    std::atomic<std::uint64_t> syncs_sent{0}, tpdos_received{0}, missed_sync_answers{0},
        late_tpdos{0}, malformed_frames{0}, unexpected_frames{0}, tx_queue_full{0}, emergencies{0},
        error_frames{0}, boot_ups{0}, bus_faults{0}, reconfigurations{0},
        reconfiguration_failures{0}, receive_cap_reached{0}, frames_sent{0}, frames_received{0},
        bus_bits{0}, homings{0}, homing_failures{0};
  } counters_;
};

}  // namespace cambio::canopen
