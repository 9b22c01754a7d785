#include "cambio/canopen/can_joint_group.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "cambio/canopen/can_bus_load.hpp"

namespace cambio::canopen {

CanJointGroup::CanJointGroup(hal::JointGroupInfo info, CanGroupSettings settings,
                             std::vector<JointDriveInfo> drives, double rate_hz, hal::CanBus& bus,
                             const hal::Clock& clock)
    : info_(std::move(info)),
      settings_(settings),
      rate_hz_(rate_hz),
      bus_(bus),
      clock_(clock),
      stale_after_syncs_(std::max(1, settings_.stale_after_missed_syncs)),
      sdo_timeout_ns_(static_cast<std::int64_t>(std::llround(settings_.sdo_timeout_s * 1e9))) {
  if (drives.size() != info_.joints.size() || info_.limits.size() != info_.joints.size()) {
    throw std::invalid_argument("CAN joint group '" + info_.name +
                                "': one drive and one set of limits per joint are needed");
  }
  if (!(rate_hz > 0.0)) {
    throw std::invalid_argument("CAN joint group '" + info_.name + "': rate must be > 0 Hz");
  }
  const hal::CommandMode mode = drives.empty() ? hal::CommandMode::kPosition : drives[0].mode;
  layout_ = pdo_layout(mode, settings_);
  slot_of_node_.fill(-1);
  const auto heartbeat_ns =
      static_cast<std::int64_t>(std::llround(settings_.heartbeat_period_s * 1e9));
  for (std::size_t k = 0; k < drives.size(); ++k) {
    const JointDriveInfo& drive = drives[k];
    const std::string joint =
        "CAN joint group '" + info_.name + "', joint '" + info_.joints[k] + "'";
    if (drive.node_id < kMinNodeId || drive.node_id > kMaxNodeId) {
      throw std::invalid_argument(joint + ": node id " + std::to_string(drive.node_id) +
                                  " is outside 1..127");
    }
    if (slot_of_node_[static_cast<std::size_t>(drive.node_id)] >= 0) {
      throw std::invalid_argument(joint + ": node id " + std::to_string(drive.node_id) +
                                  " is used twice in the group");
    }
    if (drive.mode != mode) {
      throw std::invalid_argument(joint + ": every drive of a group runs the same mode (the " +
                                  "PDO layout is per group)");
    }
    if (drive.encoder_counts_per_rev <= 0 || !std::isfinite(drive.gear_ratio) ||
        drive.gear_ratio == 0.0) {
      throw std::invalid_argument(joint + ": encoder_counts_per_rev must be > 0 and gear_ratio " +
                                  "finite and non-zero");
    }
    slot_of_node_[static_cast<std::size_t>(drive.node_id)] = static_cast<std::int16_t>(k);
    Slot slot;
    slot.drive = Cia402Drive(drive.node_id,
                             cia402::Units::from(drive.gear_ratio, drive.encoder_counts_per_rev),
                             drive.mode);
    slot.heartbeat = HeartbeatConsumer(heartbeat_ns);
    slot.drive.set_torque_units({0.0, drive.gear_ratio});
    slot.must_home = drive.homing.has_value();
    if (drive.homing) slot.homing = *drive.homing;
    slots_.push_back(slot);
  }
  // RPDO1 (and RPDO2 when mapped) per drive, then SYNC.
  const std::size_t per_drive = layout_.rpdos[1].empty() ? 1 : 2;
  // One more for the reconfiguration's or the homing's SDO request (or NMT start).
  tx_.resize(slots_.size() * per_drive + 2);
}

void CanJointGroup::seed_feedback(std::size_t joint, const DriveFeedback& feedback,
                                  std::int64_t stamp_ns) {
  slots_[joint].drive.on_feedback(feedback);
  slots_[joint].stamp_ns = stamp_ns;
}

void CanJointGroup::set_rated_torque(std::size_t joint, double rated_torque_nm) {
  slots_[joint].drive.set_torque_units(
      {rated_torque_nm, slots_[joint].drive.torque_units().gear_ratio});
}

void CanJointGroup::set_configuration(std::size_t joint, std::span<const ObjectWrite> writes) {
  slots_[joint].configuration = reconfiguration_plan(writes);
}

void CanJointGroup::set_homed(std::size_t joint, HomingRecord record) {
  slots_[joint].homed = true;
  homing_records_.push_back(std::move(record));
}

std::vector<HomingRecord> CanJointGroup::homing_records() const {
  std::vector<HomingRecord> records = homing_records_;
  for (std::size_t i = 0; i < std::min(loop_homing_count_, loop_homings_.size()); ++i) {
    const LoopHoming& homed = loop_homings_[i];
    const Slot& slot = slots_[homed.joint];
    HomingRecord record;
    record.joint = info_.joints[homed.joint];
    record.node_id = slot.drive.node_id();
    record.method = slot.homing.method;
    record.duration_s = homed.duration_s;
    record.statuswords.assign(
        homed.statuswords.begin(),
        homed.statuswords.begin() + static_cast<std::ptrdiff_t>(homed.statusword_count));
    record.feedback = homed.feedback;
    record.on_request = true;
    records.push_back(std::move(record));
  }
  return records;
}

HomingError CanJointGroup::last_homing_error() const {
  HomingError error;
  (void)last_homing_error_.read(error);
  return error;
}

ReconfigurationError CanJointGroup::last_reconfiguration_error() const {
  ReconfigurationError error;
  (void)last_error_.read(error);
  return error;
}

void CanJointGroup::arm(std::int64_t now_ns) {
  for (Slot& slot : slots_) {
    slot.heartbeat.arm(now_ns);
    slot.missed_syncs = 0;
    slot.answered = false;
  }
  sync_to_check_ = false;
}

bool CanJointGroup::faulted_or_lost(const Slot& slot) const {
  return hal::is_faulted(slot.drive.state()) || slot.heartbeat.lost() ||
         slot.heartbeat.rebooted() || bus_fault_;
}

namespace {
bool bus_is_down(hal::CanBusState state) {
  return state == hal::CanBusState::kBusOff || state == hal::CanBusState::kDown;
}
}  // namespace

void CanJointGroup::check_bus() {
  if (bus_fault_ || !bus_is_down(bus_.status().state)) return;
  bus_fault_ = true;
  bump(counters_.bus_faults);
}

void CanJointGroup::run_reconfiguration(std::int64_t now_ns) {
  if (reconfiguring_ >= 0) {
    Slot& slot = slots_[static_cast<std::size_t>(reconfiguring_)];
    reconfiguration_.poll(now_ns);
    if (reconfiguration_.state() == NodeReconfiguration::State::kDone) {
      // Configured, verified and started: the SDO answers show it alive, so its heartbeat (now
      // configured again) has three periods from here.
      slot.heartbeat.clear_rebooted();
      slot.heartbeat.clear_lost();
      slot.heartbeat.arm(now_ns);
      slot.drive.on_feedback(reconfiguration_.feedback());
      slot.stamp_ns = now_ns;
      slot.missed_syncs = 0;
      slot.reconfiguration_requested = false;
      bump(counters_.reconfigurations);
      reconfiguring_ = -1;
    } else if (reconfiguration_.state() == NodeReconfiguration::State::kFailed) {
      // Stays rebooted (comm lost); a later fault reset tries again.
      slot.reconfiguration_requested = false;
      last_error_.write(reconfiguration_.error());
      bump(counters_.reconfiguration_failures);
      reconfiguring_ = -1;
    }
  }
  // One at a time, never beside a homing, and not while the bus is off or a failed run's abort
  // is still to go out.
  if (reconfiguring_ >= 0 || bus_fault_ || reconfiguration_.has_pending() || homing_joint_ >= 0 ||
      homing_.has_pending()) {
    return;
  }
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    Slot& slot = slots_[k];
    if (!slot.reconfiguration_requested) continue;
    if (slot.configuration.empty()) {
      slot.reconfiguration_requested = false;
      ReconfigurationError error;
      error.node_id = slot.drive.node_id();
      std::snprintf(error.text.data(), error.text.size(),
                    "node %d: rebooted, and no configuration was recorded to replay",
                    slot.drive.node_id());
      last_error_.write(error);
      bump(counters_.reconfiguration_failures);
      continue;
    }
    reconfiguration_.start(slot.drive.node_id(), slot.configuration, sdo_timeout_ns_, now_ns);
    reconfiguring_ = static_cast<int>(k);
    return;
  }
}

const hal::CanFrame* CanJointGroup::extra_frame() const {
  if (reconfiguration_.has_pending()) return &reconfiguration_.pending_frame();
  if (homing_.has_pending()) return &homing_.pending_frame();
  return nullptr;
}

void CanJointGroup::run_homing(std::int64_t now_ns) {
  if (homing_joint_ >= 0) {
    const auto joint = static_cast<std::size_t>(homing_joint_);
    Slot& slot = slots_[joint];
    if (homing_.running()) {
      if (slot.answered) homing_.on_statusword(slot.drive.feedback().statusword, now_ns);
      homing_.poll(now_ns);
      if (hold_latched_ || bus_fault_) homing_.stop(HomingFailure::kStopped, now_ns);
    }
    if (homing_.state() == HomingSequencer::State::kDone) {
      slot.homed = true;
      if (loop_homing_count_ < loop_homings_.size()) {
        LoopHoming& record = loop_homings_[loop_homing_count_];
        record.joint = joint;
        record.duration_s = homing_.duration_s();
        const auto words = homing_.statuswords();
        std::copy(words.begin(), words.end(), record.statuswords.begin());
        record.statusword_count = words.size();
        record.feedback = slot.drive.feedback();
      }
      ++loop_homing_count_;
      bump(counters_.homings);
      homing_joint_ = -1;
    } else if (homing_.state() == HomingSequencer::State::kFailed) {
      // Stays unhomed: disabled, never driven, until homed again.
      last_homing_error_.write(homing_.error());
      bump(counters_.homing_failures);
      homing_joint_ = -1;
    }
  }
  if (homing_joint_ >= 0 || reconfiguring_ >= 0 || reconfiguration_.has_pending() ||
      homing_.has_pending() || hold_latched_ || bus_fault_) {
    return;  // A homing asked while the group holds waits for the hold to end.
  }
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    Slot& slot = slots_[k];
    if (!slot.home_requested) continue;
    slot.home_requested = false;
    slot.homed = false;  // Its reference is being redefined: not driven until done.
    const auto homing_timeout_ns =
        static_cast<std::int64_t>(std::llround(slot.homing.timeout_s * 1e9));
    // A state change or an SDO answer: the SDO timeout, and at least 20 cycles.
    const std::int64_t step_timeout_ns =
        std::max(sdo_timeout_ns_, static_cast<std::int64_t>(std::llround(20e9 / rate_hz_)));
    homing_.start(slot.drive.node_id(), slot.homing.method, homing_timeout_ns, step_timeout_ns,
                  slot.drive.mode() == hal::CommandMode::kPosition
                      ? cia402::Mode::kCyclicSynchronousPosition
                      : cia402::Mode::kCyclicSynchronousVelocity,
                  now_ns);
    homing_joint_ = static_cast<int>(k);
    return;
  }
}

void CanJointGroup::on_tpdo(Slot& slot, int pdo, const hal::CanFrame& frame,
                            std::int64_t stamp_ns) {
  const PdoMapping& mapping = layout_.tpdos[static_cast<std::size_t>(pdo)];
  DriveFeedback feedback = slot.drive.feedback();
  if (mapping.empty() ||
      !unpack_pdo(mapping, frame,
                  [&feedback](ObjectAddress object, std::uint32_t raw, std::size_t bytes) {
                    store_feedback(feedback, object, raw, bytes);
                  })) {
    bump(counters_.malformed_frames);
    return;
  }
  bump(counters_.tpdos_received);
  slot.drive.on_feedback(feedback);
  if (pdo != 0) return;
  // TPDO1 is the answer to a SYNC. One that arrived before the last SYNC went out, or a second
  // one in the same cycle, answered an earlier SYNC: late.
  if (slot.answered || (last_sync_ns_ > 0 && stamp_ns < last_sync_ns_)) {
    bump(counters_.late_tpdos);
  }
  slot.answered = true;
  slot.missed_syncs = 0;
  slot.stamp_ns = stamp_ns;
}

void CanJointGroup::dispatch(const hal::CanFrame& frame, std::int64_t now_ns) {
  if (frame.error_frame) {
    bump(counters_.error_frames);
    return;
  }
  const std::int64_t stamp_ns = frame.stamp_ns > 0 ? frame.stamp_ns : now_ns;
  const int node = node_of(frame.id);
  const std::int16_t index =
      frame.extended_id || frame.id > 0x7FF ? -1 : slot_of_node_[static_cast<std::size_t>(node)];
  if (index < 0 || node == 0) {
    bump(counters_.unexpected_frames);
    return;
  }
  Slot& slot = slots_[static_cast<std::size_t>(index)];
  switch (function_of(frame.id)) {
    case 0x180:
      on_tpdo(slot, 0, frame, stamp_ns);
      return;
    case 0x280:
      on_tpdo(slot, 1, frame, stamp_ns);
      return;
    case 0x080: {
      const auto emergency = decode_emergency(frame);
      if (!emergency) {
        bump(counters_.malformed_frames);
        return;
      }
      bump(counters_.emergencies);
      slot.emergency.on_emergency(*emergency);
      return;
    }
    case 0x580:
      if (reconfiguring_ == index) {
        reconfiguration_.on_frame(frame, now_ns);
      } else if (homing_joint_ == index) {
        homing_.on_sdo_frame(frame, now_ns);
      } else {
        bump(counters_.unexpected_frames);
      }
      return;
    case 0x700: {
      const auto state = heartbeat_state(frame);
      if (!state) {
        bump(counters_.malformed_frames);
        return;
      }
      if (*state == NmtState::kBootUp) {
        bump(counters_.boot_ups);
        slot.homed = false;  // A drive that restarted has lost its reference.
        if (reconfiguring_ == index) reconfiguration_.fail("booted again while being configured");
        if (homing_joint_ == index) homing_.on_boot_up(now_ns);
      }
      slot.heartbeat.on_heartbeat(*state, stamp_ns);
      return;
    }
    default:
      bump(counters_.unexpected_frames);
      return;
  }
}

hal::Status CanJointGroup::read(std::span<hal::JointState> out, std::int64_t& stamp_ns) {
  if (out.size() != slots_.size()) return hal::Status::kRejected;
  const std::int64_t now_ns = clock_.now_ns();
  hal::CanFrame frame;
  std::size_t received = 0;
  const std::size_t cap = max_frames_per_read();
  std::uint64_t received_bits = 0;
  while (received < cap && bus_.receive(frame) == hal::Status::kOk) {
    dispatch(frame, now_ns);
    if (!frame.error_frame)
      received_bits += static_cast<std::uint64_t>(can_frame_worst_case_bits(frame.length));
    ++received;
  }
  bump(counters_.frames_received, received);
  bump(counters_.bus_bits, received_bits);
  if (received == cap) bump(counters_.receive_cap_reached);
  check_bus();
  run_reconfiguration(now_ns);

  if (sync_to_check_) {
    for (Slot& slot : slots_) {
      if (!slot.answered) {
        ++slot.missed_syncs;
        bump(counters_.missed_sync_answers);
      }
    }
    sync_to_check_ = false;
  }
  bool any_fault = false;
  for (Slot& slot : slots_) {
    (void)slot.heartbeat.check(now_ns);
    any_fault = any_fault || faulted_or_lost(slot);
  }
  // Latched until a fault reset finds every drive out of its fault and heard again.
  hold_latched_ = hold_latched_ || any_fault;
  if (reset_pending_ && !any_fault) {
    hold_latched_ = false;
    reset_pending_ = false;
  }
  run_homing(now_ns);

  hal::Status status = hal::Status::kOk;
  stamp_ns = 0;
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    const Slot& slot = slots_[k];
    hal::JointState& state = out[k];
    const DriveFeedback& feedback = slot.drive.feedback();
    const cia402::Units& units = slot.drive.units();
    state.position_rad = units.to_rad(feedback.position_counts);
    state.velocity_rad_s =
        layout_.tpdos[1].empty() ? 0.0 : units.to_rad(feedback.velocity_counts_s);
    // Torque actual is per mille of the motor's rated torque; the gear multiplies it.
    state.effort_nm = slot.drive.torque_units().to_joint_nm(feedback.torque_per_mille);
    state.stamp_ns = slot.stamp_ns;
    state.error_code = slot.emergency.error_code;
    state.drive_state = slot.drive.state();
    std::uint32_t bits = slot.clamped_bits;
    if (hal::is_faulted(slot.drive.state())) bits |= hal::kJointFault;
    if (!hal::is_enabled(slot.drive.state())) bits |= hal::kJointNotEnabled;
    if (slot.heartbeat.lost() || slot.heartbeat.rebooted() || bus_fault_) {
      bits |= hal::kJointCommLost;
    }
    if (slot.missed_syncs >= stale_after_syncs_) bits |= hal::kJointStale;
    if (homing_joint_ == static_cast<int>(k)) bits |= hal::kJointHoming | hal::kJointNotEnabled;
    state.status_bits = bits;
    if ((bits & hal::kJointLatchingBits) != 0) status = hal::Status::kFault;
    stamp_ns = std::max(stamp_ns, slot.stamp_ns);
  }
  return status;
}

void CanJointGroup::build_rpdos(bool use_commands) {
  tx_count_ = 0;
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    Slot& slot = slots_[k];
    hal::JointCommand command = slot.command;
    if (!use_commands) {
      // No write() this cycle: hold where the joint is.
      command = {slot.drive.mode(),
                 slot.drive.mode() == hal::CommandMode::kPosition ? slot.drive.position_rad() : 0.0,
                 0.0, 0.0};
    }
    const bool unhomed = slot.must_home && !slot.homed;
    DriveTargets targets = slot.drive.next_targets(command, hold_latched_, unhomed);
    if (homing_joint_ == static_cast<int>(k)) {
      // The homing's controlword; in mode 6 the drive moves itself, the target is not used.
      targets = {};
      targets.controlword = homing_.controlword();
      targets.target_position_counts = slot.drive.feedback().position_counts;
    }
    const auto value_of = [&targets](ObjectAddress object) { return raw_target(targets, object); };
    pack_pdo(layout_.rpdos[0], rpdo_cob_id(1, slot.drive.node_id()), value_of, tx_[tx_count_++]);
    if (!layout_.rpdos[1].empty()) {
      pack_pdo(layout_.rpdos[1], rpdo_cob_id(2, slot.drive.node_id()), value_of, tx_[tx_count_++]);
    }
  }
  tx_[tx_count_++] = sync_frame();
  // After SYNC: the cycle's PDOs keep their timing.
  if (const hal::CanFrame* extra = extra_frame()) tx_[tx_count_++] = *extra;
}

hal::Status CanJointGroup::write(std::span<const hal::JointCommand> commands) {
  if (commands.size() != slots_.size()) return hal::Status::kRejected;
  for (std::size_t k = 0; k < slots_.size(); ++k) {
    Slot& slot = slots_[k];
    slot.command = commands[k];
    const bool clamped = hal::clamp_command(slot.command, info_.limits[k]);
    slot.clamped_bits = clamped ? hal::kJointCommandClamped : 0u;
  }
  build_rpdos(true);
  written_ = true;
  return hal::Status::kOk;
}

hal::Status CanJointGroup::sync() {
  if (!written_) build_rpdos(false);
  written_ = false;
  const std::size_t sent = bus_.send_batch(std::span(tx_).first(tx_count_));
  std::uint64_t sent_bits = 0;
  for (std::size_t i = 0; i < sent; ++i) {
    sent_bits += static_cast<std::uint64_t>(can_frame_worst_case_bits(tx_[i].length));
  }
  bump(counters_.frames_sent, sent);
  bump(counters_.bus_bits, sent_bits);
  const std::int64_t now_ns = clock_.now_ns();
  const bool with_sdo = extra_frame() != nullptr;
  const std::size_t sync_count = tx_count_ - (with_sdo ? 1 : 0);
  // A pending frame that did not go out is offered again next cycle.
  if (with_sdo && sent == tx_count_) {
    if (reconfiguration_.has_pending()) {
      reconfiguration_.on_sent(now_ns);
    } else {
      homing_.on_sent();
    }
  }
  if (sent < sync_count) {
    check_bus();
    if (bus_fault_) return hal::Status::kFault;
    bump(counters_.tx_queue_full, tx_count_ - sent);
    return hal::Status::kNoNewData;
  }
  bump(counters_.syncs_sent);
  last_sync_ns_ = now_ns;
  sync_to_check_ = true;
  for (Slot& slot : slots_) slot.answered = false;
  return hal::Status::kOk;
}

hal::Status CanJointGroup::request(hal::DriveRequest request, int joint) {
  const int count = static_cast<int>(slots_.size());
  if (joint != kAllJoints && (joint < 0 || joint >= count)) return hal::Status::kRejected;
  const int first = joint == kAllJoints ? 0 : joint;
  const int last = joint == kAllJoints ? count : joint + 1;
  if (request == hal::DriveRequest::kHome) {
    if (joint != kAllJoints && !slots_[static_cast<std::size_t>(joint)].must_home) {
      return hal::Status::kRejected;  // Its encoder is absolute: nothing to home.
    }
    for (int k = first; k < last; ++k) {
      Slot& slot = slots_[static_cast<std::size_t>(k)];
      // Every joint: those that lost (or never had) their reference; one joint: again.
      const bool wanted = joint != kAllJoints || !slot.homed;
      if (slot.must_home && wanted && homing_joint_ != k) slot.home_requested = true;
    }
    return hal::Status::kOk;
  }
  for (int k = first; k < last; ++k) {
    Slot& slot = slots_[static_cast<std::size_t>(k)];
    slot.drive.request(request);
    if (request == hal::DriveRequest::kFaultReset) {
      slot.emergency.clear();
      slot.heartbeat.clear_lost();
      // Replayed from read(), once the bus is back.
      if (slot.heartbeat.rebooted() && reconfiguring_ != k) slot.reconfiguration_requested = true;
    }
  }
  // The bus is cleared once it carries frames again; a bus still off re-latches at once.
  if (request == hal::DriveRequest::kFaultReset && bus_fault_ &&
      !bus_is_down(bus_.status().state)) {
    bus_fault_ = false;
  }
  if (request == hal::DriveRequest::kFaultReset) reset_pending_ = true;
  return hal::Status::kOk;
}

CanGroupCounters CanJointGroup::counters() const {
  const auto load = [](const std::atomic<std::uint64_t>& counter) {
    return counter.load(std::memory_order_relaxed);
  };
  return {load(counters_.syncs_sent),
          load(counters_.tpdos_received),
          load(counters_.missed_sync_answers),
          load(counters_.late_tpdos),
          load(counters_.malformed_frames),
          load(counters_.unexpected_frames),
          load(counters_.tx_queue_full),
          load(counters_.emergencies),
          load(counters_.error_frames),
          load(counters_.boot_ups),
          load(counters_.bus_faults),
          load(counters_.reconfigurations),
          load(counters_.reconfiguration_failures),
          load(counters_.receive_cap_reached),
          load(counters_.frames_sent),
          load(counters_.frames_received),
          load(counters_.bus_bits),
          load(counters_.homings),
          load(counters_.homing_failures)};
}

std::size_t CanJointGroup::shutdown_frames(std::uint16_t controlword,
                                           std::span<hal::CanFrame> out) const {
  std::size_t count = 0;
  for (const Slot& slot : slots_) {
    if (count >= out.size()) return count;
    DriveTargets targets;
    targets.controlword = controlword;
    targets.target_position_counts = slot.drive.feedback().position_counts;
    pack_pdo(
        layout_.rpdos[0], rpdo_cob_id(1, slot.drive.node_id()),
        [&targets](ObjectAddress object) { return raw_target(targets, object); }, out[count++]);
  }
  if (count < out.size()) out[count++] = sync_frame();
  return count;
}

}  // namespace cambio::canopen
