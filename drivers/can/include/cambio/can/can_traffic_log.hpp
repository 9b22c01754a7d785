#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cambio/hal/can_bus.hpp"

namespace cambio::can {

/// What a traffic log did, from close().
struct CanLogReport {
  std::uint64_t records_written = 0;
  std::uint64_t records_dropped = 0;  ///< Lost to a full ring (the writer fell behind).
  std::string error;                  ///< First write/close failure, naming the file; "" if none.
  /// From abandon(): where this run's frames were left (the log's path is unchanged).
  std::string abandoned_path;
  bool ok() const { return error.empty() && records_dropped == 0; }
};

/// The `--can-log FILE` writer: frames recorded by LoggingCanBus decorators (one per bus, each
/// with its own single-producer ring) are written by one background thread in can-utils'
/// `candump -L` format (candump_log.hpp), so `canplayer -I FILE` replays them.
/// Record times are wall-clock (CLOCK_REALTIME), as candump writes: a sent frame's is when
/// send() took it; a received frame's is its stamp_ns (CLOCK_MONOTONIC, as SocketCanBus gives)
/// mapped to wall clock, or when receive() returned it if stamp_ns is 0 or
/// `frame_stamps_on_monotonic` is false (e.g. an in-process bus on a simulated clock).
class CanTrafficLog {
 public:
  /// Starts the writer on a new file beside `path` (PATH.cambio-partial-PID), which close() puts
  /// in place: whatever `path` held stays whole until then. A `path` that is a FIFO or a device
  /// is written directly. `ring_capacity`: records per bus between two drains (rounded up to a
  /// power of two). Throws std::runtime_error naming the file.
  explicit CanTrafficLog(const std::string& path, std::size_t ring_capacity = 8192,
                         bool frame_stamps_on_monotonic = true);
  ~CanTrafficLog();  ///< abandon() unless closed, saying where the frames went.
  CanTrafficLog(const CanTrafficLog&) = delete;
  CanTrafficLog& operator=(const CanTrafficLog&) = delete;

  /// Drains every ring, writes and closes the file, checking every write; then reports.
  /// Frames recorded afterwards are counted as dropped. Idempotent. Not for a loop.
  CanLogReport close();
  /// For a run that never started: drains and closes as close() does, but leaves `path` as it
  /// was and this run's frames in PATH.incomplete (CanLogReport::abandoned_path). Idempotent;
  /// after close() it does nothing.
  CanLogReport abandon();
  const std::string& path() const { return path_; }
  /// Records lost to full rings so far. Thread-safe.
  std::uint64_t records_dropped() const;

  class Ring;  // single producer (the bus's loop thread), single consumer (the writer)

 private:
  friend class LoggingCanBus;
  std::shared_ptr<Ring> add_ring(std::string interface);
  void writer_loop();
  std::size_t drain();
  void write_out(const char* data, std::size_t size);
  void finish();  ///< Stops the writer, drains, closes the file; fills report_.

  std::string path_;
  std::string staging_path_;  ///< Where frames go until close(); empty when written directly.
  std::size_t ring_capacity_;
  bool stamps_on_monotonic_;
  int file_ = -1;
  mutable std::mutex
      rings_mutex_;  // only between add_ring() and the writer; never on the loop side
  std::vector<std::shared_ptr<Ring>> rings_;
  std::vector<char> buffer_;
  std::size_t buffered_ = 0;
  std::uint64_t written_ = 0;
  std::string error_;
  std::atomic<bool> stop_{false};
  bool closed_ = false;
  CanLogReport report_;
  std::thread writer_;
};

/// A hal::CanBus that records every frame sent (accepted by the bus) and received into a
/// CanTrafficLog, and otherwise forwards to the bus it owns. send/receive stay real-time safe:
/// a record is one copy into a preallocated lock-free ring; a full ring drops the record and
/// counts it (CanTrafficLog::records_dropped), never blocks.
class LoggingCanBus final : public hal::CanBus {
 public:
  /// `log` must stay open while frames go through (records after close() count as dropped).
  /// Allocates the bus's ring: call at configure time.
  LoggingCanBus(std::unique_ptr<hal::CanBus> bus, CanTrafficLog& log);
  ~LoggingCanBus() override;

  const std::string& name() const override { return bus_->name(); }
  hal::Status send(const hal::CanFrame& frame) override;
  hal::Status receive(hal::CanFrame& out) override;
  hal::CanBusStatus status() const override { return bus_->status(); }
  std::size_t send_batch(std::span<const hal::CanFrame> frames) override;
  hal::Status wait_for_frame(std::int64_t timeout_ns) override {
    return bus_->wait_for_frame(timeout_ns);
  }
  hal::CanBus& inner() { return *bus_; }

 private:
  std::unique_ptr<hal::CanBus> bus_;
  std::shared_ptr<CanTrafficLog::Ring> ring_;
  bool stamps_on_monotonic_;
};

}  // namespace cambio::can
