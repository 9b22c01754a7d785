#pragma once

// A minimal CiA 402 drive written for these tests, independently of the master's code: an object
// dictionary, an SDO server (expedited, and segmented both ways, with toggle bits as CiA 301
// §7.2.4.3 draws them), NMT (boot-up on reset), PDOs as mapped over SDO, and an ideal CSP axis
// (the position follows the target at each SYNC). Steps when the test calls step().

#include <cstdint>
#include <map>
#include <vector>

#include "cambio/hal/can_bus.hpp"
#include "cambio/hal/drive_state.hpp"

namespace cambio::canopen::testing {

class TestDrive {
 public:
  TestDrive(hal::CanBus& bus, int node_id)
      : bus_(bus), node_id_(static_cast<std::uint32_t>(node_id)) {
    set(0x1000, 0, 0x0002'0192, 4);  // CiA 402 servo drive.
    set(0x6041, 0, 0x0040, 2);       // Switch on disabled.
    set(0x6064, 0, 0, 4);
    set(0x6076, 0, 2000, 4);
    const char* name = "Test drive, a name longer than four bytes";
    std::vector<std::uint8_t> text(name, name + 41);
    od_[key(0x1008, 0)] = text;
    factory_ = od_;
  }

  static std::uint32_t key(std::uint16_t index, std::uint8_t subindex) {
    return static_cast<std::uint32_t>(index) << 8 | subindex;
  }
  void set(std::uint16_t index, std::uint8_t subindex, std::uint32_t value, int bytes) {
    std::vector<std::uint8_t> data(static_cast<std::size_t>(bytes));
    for (int i = 0; i < bytes; ++i)
      data[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(value >> (8 * i));
    od_[key(index, subindex)] = data;
  }
  std::uint32_t get(std::uint16_t index, std::uint8_t subindex) const {
    const auto it = od_.find(key(index, subindex));
    std::uint32_t value = 0;
    if (it == od_.end()) return 0;
    for (std::size_t i = 0; i < it->second.size() && i < 4; ++i)
      value |= std::uint32_t{it->second[i]} << (8 * i);
    return value;
  }
  bool has(std::uint16_t index, std::uint8_t subindex) const {
    return od_.count(key(index, subindex)) != 0;
  }

  /// Every SDO download the drive accepted, in order: (index, sub, value).
  struct Write {
    std::uint16_t index;
    std::uint8_t subindex;
    std::uint32_t value;
    std::size_t bytes;
  };
  std::vector<Write> writes;
  /// Every frame the drive received.
  std::vector<hal::CanFrame> received;

  // Behaviour knobs.
  bool answer_sync = true;
  bool answer_sdo = true;
  /// Objects whose written value the drive replaces with its own (a parameter it refuses).
  std::map<std::uint32_t, std::uint32_t> clamp_on_write;

  hal::DriveState state = hal::DriveState::kSwitchOnDisabled;
  std::uint8_t nmt_state = 0x7F;
  std::int32_t position_counts = 0;
  std::uint16_t last_controlword = 0;
  std::int32_t last_target = 0;
  std::vector<std::uint16_t> controlwords_at_sync;
  std::vector<std::int32_t> targets_at_sync;
  std::int16_t last_torque_offset = 0;       ///< 0x60B2 from RPDO2, per mille.
  std::int16_t torque_actual_per_mille = 0;  ///< 0x6077 sent in TPDO2.

  void step() {
    hal::CanFrame frame;
    while (bus_.receive(frame) == hal::Status::kOk) {
      received.push_back(frame);
      handle(frame);
    }
  }

  void send_heartbeat() { send_simple(0x700u + node_id_, {nmt_state}); }
  void send_boot_up() {
    nmt_state = 0x7F;
    send_simple(0x700u + node_id_, {0x00});
  }
  void send_emcy(std::uint16_t code, std::uint8_t error_register) {
    send_simple(0x080u + node_id_,
                {static_cast<std::uint8_t>(code), static_cast<std::uint8_t>(code >> 8),
                 error_register, 0, 0, 0, 0, 0});
  }
  void fault() { state = hal::DriveState::kFault; }
  /// A power cycle: the dictionary back to its factory values (parameters and PDO mappings
  /// gone), switch on disabled, pre-operational, boot-up sent. The axis stays where it is.
  void reboot() {
    od_ = factory_;
    state = hal::DriveState::kSwitchOnDisabled;
    previous_controlword_ = 0;
    last_controlword = 0;
    writes.clear();
    send_boot_up();
  }

 private:
  void send_simple(std::uint32_t id, std::vector<std::uint8_t> data) {
    hal::CanFrame frame;
    frame.id = id;
    frame.length = static_cast<std::uint8_t>(data.size());
    for (std::size_t i = 0; i < data.size(); ++i) frame.data[i] = data[i];
    (void)bus_.send(frame);
  }
  void sdo_reply(std::vector<std::uint8_t> data) {
    data.resize(8, 0);
    send_simple(0x580u + node_id_, data);
  }
  void sdo_abort(std::uint16_t index, std::uint8_t sub, std::uint32_t code) {
    sdo_reply({0x80, static_cast<std::uint8_t>(index), static_cast<std::uint8_t>(index >> 8), sub,
               static_cast<std::uint8_t>(code), static_cast<std::uint8_t>(code >> 8),
               static_cast<std::uint8_t>(code >> 16), static_cast<std::uint8_t>(code >> 24)});
  }

  void store(std::uint16_t index, std::uint8_t sub, std::vector<std::uint8_t> data) {
    std::uint32_t value = 0;
    for (std::size_t i = 0; i < data.size() && i < 4; ++i)
      value |= std::uint32_t{data[i]} << (8 * i);
    writes.push_back({index, sub, value, data.size()});
    const auto clamp = clamp_on_write.find(key(index, sub));
    if (clamp != clamp_on_write.end()) {
      set(index, sub, clamp->second, static_cast<int>(data.size()));
    } else {
      od_[key(index, sub)] = std::move(data);
    }
  }

  void handle(const hal::CanFrame& frame) {
    if (frame.id == 0x000) {
      if (frame.data[1] != 0 && frame.data[1] != node_id_) return;
      switch (frame.data[0]) {
        case 0x01:
          nmt_state = 0x05;
          break;
        case 0x02:
          nmt_state = 0x04;
          break;
        case 0x80:
          nmt_state = 0x7F;
          break;
        case 0x81:
        case 0x82:
          send_boot_up();
          break;
        default:
          break;
      }
      return;
    }
    if (frame.id == 0x600u + node_id_) {
      if (answer_sdo) handle_sdo(frame);
      return;
    }
    if (frame.id == 0x200u + node_id_) {
      // RPDO1 as mapped at 0x1600: controlword + target.
      std::size_t offset = 0;
      for (std::uint8_t sub = 1; sub <= get(0x1600, 0); ++sub) {
        const std::uint32_t entry = get(0x1600, sub);
        const std::size_t bytes = (entry & 0xFF) / 8;
        std::uint32_t value = 0;
        for (std::size_t i = 0; i < bytes; ++i)
          value |= std::uint32_t{frame.data[offset + i]} << (8 * i);
        offset += bytes;
        if ((entry >> 16) == 0x6040) last_controlword = static_cast<std::uint16_t>(value);
        if ((entry >> 16) == 0x607A || (entry >> 16) == 0x60FF)
          last_target = static_cast<std::int32_t>(value);
      }
      return;
    }
    if (frame.id == 0x300u + node_id_) {
      // RPDO2 as mapped at 0x1601: velocity offset and/or torque offset.
      std::size_t offset = 0;
      for (std::uint8_t sub = 1; sub <= get(0x1601, 0); ++sub) {
        const std::uint32_t entry = get(0x1601, sub);
        const std::size_t bytes = (entry & 0xFF) / 8;
        std::uint32_t value = 0;
        for (std::size_t i = 0; i < bytes; ++i)
          value |= std::uint32_t{frame.data[offset + i]} << (8 * i);
        offset += bytes;
        if ((entry >> 16) == 0x60B2) last_torque_offset = static_cast<std::int16_t>(value);
      }
      return;
    }
    if (frame.id == 0x080 && frame.length == 0) on_sync();
  }

  void on_sync() {
    if (nmt_state != 0x05 || !answer_sync) return;
    controlwords_at_sync.push_back(last_controlword);
    targets_at_sync.push_back(last_target);
    const hal::DriveState before = state;
    state = apply(state, last_controlword, previous_controlword_);
    previous_controlword_ = last_controlword;
    if (before == hal::DriveState::kOperationEnabled &&
        state == hal::DriveState::kOperationEnabled) {
      position_counts = last_target;  // An ideal CSP axis.
    }
    // TPDO1 as mapped at 0x1A00.
    hal::CanFrame tpdo;
    tpdo.id = 0x180u + node_id_;
    std::size_t offset = 0;
    for (std::uint8_t sub = 1; sub <= get(0x1A00, 0); ++sub) {
      const std::uint32_t entry = get(0x1A00, sub);
      const std::size_t bytes = (entry & 0xFF) / 8;
      std::uint32_t value = 0;
      if ((entry >> 16) == 0x6041) value = statusword();
      if ((entry >> 16) == 0x6064) value = static_cast<std::uint32_t>(position_counts);
      for (std::size_t i = 0; i < bytes; ++i)
        tpdo.data[offset + i] = static_cast<std::uint8_t>(value >> (8 * i));
      offset += bytes;
    }
    tpdo.length = static_cast<std::uint8_t>(offset);
    (void)bus_.send(tpdo);
    if (get(0x1A01, 0) == 0) return;
    // TPDO2 as mapped at 0x1A01: velocity actual (0 here) and/or torque actual.
    hal::CanFrame tpdo2;
    tpdo2.id = 0x280u + node_id_;
    offset = 0;
    for (std::uint8_t sub = 1; sub <= get(0x1A01, 0); ++sub) {
      const std::uint32_t entry = get(0x1A01, sub);
      const std::size_t bytes = (entry & 0xFF) / 8;
      std::uint32_t value = 0;
      if ((entry >> 16) == 0x6077) value = static_cast<std::uint16_t>(torque_actual_per_mille);
      for (std::size_t i = 0; i < bytes; ++i)
        tpdo2.data[offset + i] = static_cast<std::uint8_t>(value >> (8 * i));
      offset += bytes;
    }
    tpdo2.length = static_cast<std::uint8_t>(offset);
    (void)bus_.send(tpdo2);
  }

  std::uint16_t statusword() const {
    // CiA 402-2 Table 30, written out here rather than taken from the master's vocabulary.
    switch (state) {
      case hal::DriveState::kNotReadyToSwitchOn:
        return 0x0000;
      case hal::DriveState::kSwitchOnDisabled:
        return 0x0040;
      case hal::DriveState::kReadyToSwitchOn:
        return 0x0021;
      case hal::DriveState::kSwitchedOn:
        return 0x0033;
      case hal::DriveState::kOperationEnabled:
        return 0x0037;
      case hal::DriveState::kQuickStopActive:
        return 0x0017;
      case hal::DriveState::kFaultReactionActive:
        return 0x000F;
      case hal::DriveState::kFault:
        return 0x0008;
    }
    return 0;
  }

  // CiA 402-2 Figure 4 and Table 29, from the standard.
  static hal::DriveState apply(hal::DriveState s, std::uint16_t cw, std::uint16_t previous) {
    using S = hal::DriveState;
    if (s == S::kFault)
      return (cw & 0x80) != 0 && (previous & 0x80) == 0 ? S::kSwitchOnDisabled : s;
    if ((cw & 0x80) != 0) return s;
    if ((cw & 0x02) == 0)
      return s == S::kSwitchOnDisabled ? s : S::kSwitchOnDisabled;  // Disable voltage.
    if ((cw & 0x06) == 0x02) {                                      // Quick stop.
      if (s == S::kOperationEnabled) return S::kQuickStopActive;
      if (s == S::kReadyToSwitchOn || s == S::kSwitchedOn) return S::kSwitchOnDisabled;
      return s;
    }
    if ((cw & 0x07) == 0x06) {  // Shutdown.
      return s == S::kSwitchOnDisabled || s == S::kSwitchedOn || s == S::kOperationEnabled
                 ? S::kReadyToSwitchOn
                 : s;
    }
    if ((cw & 0x0F) == 0x07) {  // Switch on.
      return s == S::kReadyToSwitchOn || s == S::kOperationEnabled ? S::kSwitchedOn : s;
    }
    if ((cw & 0x0F) == 0x0F) {  // Enable operation.
      return s == S::kSwitchedOn || s == S::kQuickStopActive ? S::kOperationEnabled : s;
    }
    return s;
  }

  void handle_sdo(const hal::CanFrame& frame) {
    const std::uint8_t command = frame.data[0] >> 5;
    const auto index = static_cast<std::uint16_t>(frame.data[1] | frame.data[2] << 8);
    const std::uint8_t sub = frame.data[3];
    switch (command) {
      case 1: {  // Initiate download.
        if ((frame.data[0] & 0x02) != 0) {
          const std::size_t size = 4 - ((frame.data[0] >> 2) & 0x03);
          store(index, sub,
                std::vector<std::uint8_t>(frame.data.begin() + 4,
                                          frame.data.begin() + 4 + static_cast<long>(size)));
        } else {
          segment_index_ = index;
          segment_sub_ = sub;
          segment_data_.clear();
          segment_toggle_ = 0;
        }
        sdo_reply({0x60, frame.data[1], frame.data[2], sub});
        return;
      }
      case 0: {  // Download segment.
        const std::uint8_t toggle = frame.data[0] & 0x10;
        if (toggle != segment_toggle_) {
          sdo_abort(segment_index_, segment_sub_, 0x0503'0000);
          return;
        }
        const std::size_t size = 7 - ((frame.data[0] >> 1) & 0x07);
        segment_data_.insert(segment_data_.end(), frame.data.begin() + 1,
                             frame.data.begin() + 1 + static_cast<long>(size));
        if ((frame.data[0] & 0x01) != 0) store(segment_index_, segment_sub_, segment_data_);
        sdo_reply({static_cast<std::uint8_t>(0x20 | toggle)});
        segment_toggle_ ^= 0x10;
        return;
      }
      case 2: {  // Initiate upload.
        const auto it = od_.find(key(index, sub));
        if (it == od_.end()) {
          sdo_abort(index, sub, 0x0602'0000);
          return;
        }
        std::vector<std::uint8_t> data = it->second;
        if (index == 0x6041)
          data = {static_cast<std::uint8_t>(statusword()),
                  static_cast<std::uint8_t>(statusword() >> 8)};
        if (index == 0x6064) {
          data.resize(4);
          for (int i = 0; i < 4; ++i)
            data[static_cast<std::size_t>(i)] =
                static_cast<std::uint8_t>(static_cast<std::uint32_t>(position_counts) >> (8 * i));
        }
        if (data.size() <= 4) {
          std::vector<std::uint8_t> reply{static_cast<std::uint8_t>(0x43 | (4 - data.size()) << 2),
                                          frame.data[1], frame.data[2], sub};
          reply.insert(reply.end(), data.begin(), data.end());
          sdo_reply(reply);
        } else {
          upload_data_ = data;
          upload_offset_ = 0;
          segment_toggle_ = 0;
          const auto size = static_cast<std::uint32_t>(data.size());
          sdo_reply({0x41, frame.data[1], frame.data[2], sub, static_cast<std::uint8_t>(size),
                     static_cast<std::uint8_t>(size >> 8), 0, 0});
        }
        return;
      }
      case 3: {  // Upload segment.
        const std::uint8_t toggle = frame.data[0] & 0x10;
        if (toggle != segment_toggle_) {
          sdo_abort(0, 0, 0x0503'0000);
          return;
        }
        const std::size_t size = std::min<std::size_t>(7, upload_data_.size() - upload_offset_);
        const bool last = upload_offset_ + size >= upload_data_.size();
        std::vector<std::uint8_t> reply{
            static_cast<std::uint8_t>(toggle | (7 - size) << 1 | (last ? 1 : 0))};
        reply.insert(reply.end(), upload_data_.begin() + static_cast<long>(upload_offset_),
                     upload_data_.begin() + static_cast<long>(upload_offset_ + size));
        upload_offset_ += size;
        segment_toggle_ ^= 0x10;
        sdo_reply(reply);
        return;
      }
      default:
        return;
    }
  }

  hal::CanBus& bus_;
  std::uint32_t node_id_;
  std::map<std::uint32_t, std::vector<std::uint8_t>> od_;
  std::map<std::uint32_t, std::vector<std::uint8_t>> factory_;
  std::uint16_t previous_controlword_ = 0;
  std::uint16_t segment_index_ = 0;
  std::uint8_t segment_sub_ = 0;
  std::uint8_t segment_toggle_ = 0;
  std::vector<std::uint8_t> segment_data_;
  std::vector<std::uint8_t> upload_data_;
  std::size_t upload_offset_ = 0;
};

}  // namespace cambio::canopen::testing
