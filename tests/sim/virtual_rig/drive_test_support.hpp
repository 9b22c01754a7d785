#pragma once

// A test bench for one emulated drive: an in-process bus whose other end is the test, sending
// raw CANopen frames built here from CiA 301's byte layouts (no client code of the project), and
// a manual clock.

#include <gtest/gtest.h>

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cambio/can/in_process_can_bus.hpp"
#include "cambio/hal/manual_clock.hpp"
#include "cambio/virtual_rig/emulated_drive.hpp"

namespace cambio::virtual_rig::test {

inline hal::CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  hal::CanFrame f;
  f.id = id;
  f.length = static_cast<std::uint8_t>(bytes.size());
  std::size_t i = 0;
  for (std::uint8_t b : bytes) f.data[i++] = b;
  return f;
}

/// The servo of a pan joint like the shipped pan-tilt's.
inline sim::ServoParams pan_servo() {
  sim::ServoParams p;
  p.joint_name = "pan";
  p.step_s = 0.001;
  p.min_position_rad = -2.9;
  p.max_position_rad = 2.9;
  p.max_velocity_rad_s = 3.0;
  p.max_acceleration_rad_s2 = 30.0;
  p.dead_time_s = 0.002;
  p.dead_time_steps = 2;
  p.motion_noise_std_rad = 0.0002;
  p.encoder_counts_per_rev = 65536;
  p.velocity_window_steps = 10;
  return p;
}

inline EmulatedDriveConfig pan_drive(int node_id = 3) {
  EmulatedDriveConfig c;
  c.node_id = node_id;
  c.servo = pan_servo();
  c.seed = 42;
  c.initial_position_rad = 0.25;
  c.gear_ratio = 50.0;
  c.encoder_counts_per_rev = 4096;
  c.heartbeat_period_s = 0.1;
  return c;
}

struct SdoReply {
  std::uint8_t command = 0;
  std::uint32_t value = 0;  ///< Data bytes 4..7 (expedited data, size, or abort code).
  bool abort() const { return command == 0x80; }
};

class DriveBench {
 public:
  explicit DriveBench(EmulatedDriveConfig config = pan_drive())
      : network_(false, &clock_),
        master_(network_.add_endpoint("master")),
        drive_bus_(network_.add_endpoint("drive")),
        drive_(std::make_unique<EmulatedDrive>(config, drive_bus_)) {}

  EmulatedDrive& drive() { return *drive_; }
  hal::ManualClock& clock() { return clock_; }
  int node() const { return drive_->node_id(); }
  std::int64_t now_ns() const { return clock_.now_ns(); }

  void power_on() {
    drive_->power_on(clock_.now_ns());
    collect();
  }
  /// Sends frames from the test, lets the drive handle them and poll at the current time, and
  /// returns what the drive sent back.
  std::vector<hal::CanFrame> exchange(std::initializer_list<hal::CanFrame> frames) {
    for (const auto& f : frames) EXPECT_EQ(master_.send(f), hal::Status::kOk);
    return collect();
  }
  std::vector<hal::CanFrame> advance_to_ns(std::int64_t t_ns) {
    clock_.advance_to_ns(t_ns);
    return collect();
  }
  std::vector<hal::CanFrame> collect() {
    hal::CanFrame f;
    while (drive_bus_.receive(f) == hal::Status::kOk) drive_->handle(f, clock_.now_ns());
    drive_->poll(clock_.now_ns());
    std::vector<hal::CanFrame> out;
    while (master_.receive(f) == hal::Status::kOk) {
      out.push_back(f);
      log_.push_back(f);
    }
    return out;
  }
  const std::vector<hal::CanFrame>& log() const { return log_; }

  std::vector<hal::CanFrame> nmt(std::uint8_t command, int node = -1) {
    return exchange(
        {frame(0x000, {command, static_cast<std::uint8_t>(node < 0 ? this->node() : node)})});
  }
  std::vector<hal::CanFrame> sync() { return exchange({frame(0x080, {})}); }

  /// One SDO request, its single answer (fails the test when there is not exactly one).
  hal::CanFrame sdo(std::initializer_list<std::uint8_t> bytes) {
    const auto replies = exchange({frame(0x600u + static_cast<std::uint32_t>(node()), bytes)});
    std::vector<hal::CanFrame> sdo_replies;
    for (const auto& r : replies) {
      if (r.id == 0x580u + static_cast<std::uint32_t>(node())) sdo_replies.push_back(r);
    }
    EXPECT_EQ(sdo_replies.size(), 1u);
    return sdo_replies.empty() ? hal::CanFrame{} : sdo_replies.front();
  }
  SdoReply upload(std::uint16_t index, std::uint8_t sub) {
    const auto r = sdo({0x40, lo(index), hi(index), sub, 0, 0, 0, 0});
    EXPECT_EQ(r.data[1] | r.data[2] << 8, index);
    EXPECT_EQ(r.data[3], sub);
    return {r.data[0], static_cast<std::uint32_t>(r.data[4] | r.data[5] << 8 | r.data[6] << 16 |
                                                  static_cast<std::uint32_t>(r.data[7]) << 24)};
  }
  /// Expedited download with size indicated: 0x2F (1 byte), 0x2B (2), 0x27 (3), 0x23 (4).
  SdoReply download(std::uint16_t index, std::uint8_t sub, std::uint32_t value, int bytes) {
    const auto command = static_cast<std::uint8_t>(0x23 | (4 - bytes) << 2);
    const auto r =
        sdo({command, lo(index), hi(index), sub, static_cast<std::uint8_t>(value),
             static_cast<std::uint8_t>(value >> 8), static_cast<std::uint8_t>(value >> 16),
             static_cast<std::uint8_t>(value >> 24)});
    return {r.data[0], static_cast<std::uint32_t>(r.data[4] | r.data[5] << 8 | r.data[6] << 16 |
                                                  static_cast<std::uint32_t>(r.data[7]) << 24)};
  }
  /// Aborts are answered with 0x80 and the code; a confirmed download with 0x60.
  std::uint32_t write(std::uint16_t index, std::uint8_t sub, std::uint32_t value, int bytes) {
    const SdoReply reply = download(index, sub, value, bytes);
    if (reply.abort()) return reply.value;
    EXPECT_EQ(reply.command, 0x60);
    return 0;
  }

  static std::uint8_t lo(std::uint16_t v) { return static_cast<std::uint8_t>(v); }
  static std::uint8_t hi(std::uint16_t v) { return static_cast<std::uint8_t>(v >> 8); }

 private:
  hal::ManualClock clock_;
  can::InProcessCanNetwork network_;
  hal::CanBus& master_;
  hal::CanBus& drive_bus_;
  std::unique_ptr<EmulatedDrive> drive_;
  std::vector<hal::CanFrame> log_;
};

inline std::vector<hal::CanFrame> with_id(const std::vector<hal::CanFrame>& frames,
                                          std::uint32_t id) {
  std::vector<hal::CanFrame> out;
  for (const auto& f : frames) {
    if (f.id == id) out.push_back(f);
  }
  return out;
}

inline std::int32_t le_i32(const hal::CanFrame& f, std::size_t offset) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(f.data[offset]) |
                                   static_cast<std::uint32_t>(f.data[offset + 1]) << 8 |
                                   static_cast<std::uint32_t>(f.data[offset + 2]) << 16 |
                                   static_cast<std::uint32_t>(f.data[offset + 3]) << 24);
}
inline std::uint16_t le_u16(const hal::CanFrame& f, std::size_t offset) {
  return static_cast<std::uint16_t>(f.data[offset] | f.data[offset + 1] << 8);
}

}  // namespace cambio::virtual_rig::test
