#include "cambio/can/can_traffic_log.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include "cambio/can/candump_log.hpp"

namespace cambio::can {
namespace {

// How long the writer sleeps when every ring is empty: bounds the log's lag behind the bus,
// and sets the ring size needed: 8192 records cover 10 ms of a saturated 1 Mbit/s bus ~10x.
constexpr auto kWriterIdle = std::chrono::milliseconds(5);
constexpr std::size_t kWriteBufferBytes = 64 * 1024;

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace

// Lock-free single-producer single-consumer ring of records. The producer owns `tail_`, the
// consumer `head_`; each publishes its index with release and reads the other's with acquire.
class CanTrafficLog::Ring {
 public:
  struct Record {
    hal::CanFrame frame;
    std::int64_t wall_time_ns = 0;
  };

  Ring(std::string interface, std::size_t capacity)
      : interface_(std::move(interface)),
        records_(std::bit_ceil(std::max<std::size_t>(capacity, 2))),
        mask_(records_.size() - 1) {}

  const std::string& interface() const { return interface_; }

  // Producer side. Real-time safe.
  void push(const hal::CanFrame& frame, std::int64_t wall_time_ns) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (closed_.load(std::memory_order_relaxed) ||
        tail - head_.load(std::memory_order_acquire) == records_.size()) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    Record& slot = records_[tail & mask_];
    slot.frame = frame;
    slot.wall_time_ns = wall_time_ns;
    tail_.store(tail + 1, std::memory_order_release);
  }

  // Consumer side: calls `f(record)` for each record queued now; returns how many.
  template <typename F>
  std::size_t pop_all(F&& f) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t tail = tail_.load(std::memory_order_acquire);
    for (std::size_t i = head; i != tail; ++i) f(records_[i & mask_]);
    head_.store(tail, std::memory_order_release);
    return tail - head;
  }

  void close() { closed_.store(true, std::memory_order_relaxed); }
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  std::string interface_;
  std::vector<Record> records_;
  std::size_t mask_;
  alignas(64) std::atomic<std::size_t> head_{0};
  alignas(64) std::atomic<std::size_t> tail_{0};
  alignas(64) std::atomic<std::uint64_t> dropped_{0};
  std::atomic<bool> closed_{false};
};

CanTrafficLog::CanTrafficLog(const std::string& path, std::size_t ring_capacity,
                             bool frame_stamps_on_monotonic)
    : path_(path),
      ring_capacity_(ring_capacity),
      stamps_on_monotonic_(frame_stamps_on_monotonic),
      buffer_(kWriteBufferBytes) {
  // A regular file (or none yet) is written beside and put in place by close(), so a run that
  // never starts leaves the user's earlier log whole; a FIFO or device is written directly.
  struct stat existing {};
  if (::stat(path.c_str(), &existing) == 0 && !S_ISREG(existing.st_mode)) {
    file_ = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  } else {
    staging_path_ = path + ".cambio-partial-" + std::to_string(::getpid());
    file_ = ::open(staging_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  }
  if (file_ < 0) {
    throw std::runtime_error("cannot open the CAN log '" + path + "': " + std::strerror(errno));
  }
  writer_ = std::thread([this] { writer_loop(); });
}

CanTrafficLog::~CanTrafficLog() {
  const bool collected = closed_;
  const CanLogReport report = abandon();
  if (!collected && !report.abandoned_path.empty()) {
    std::fprintf(stderr, "CAN log %s: left unchanged; this run's frames are in %s\n", path_.c_str(),
                 report.abandoned_path.c_str());
  }
}

std::shared_ptr<CanTrafficLog::Ring> CanTrafficLog::add_ring(std::string interface) {
  auto ring = std::make_shared<Ring>(std::move(interface), ring_capacity_);
  const std::lock_guard lock(rings_mutex_);
  if (closed_) ring->close();
  rings_.push_back(ring);
  return ring;
}

std::uint64_t CanTrafficLog::records_dropped() const {
  // The writer never removes rings, and add_ring() is called at configure time only.
  const std::lock_guard lock(rings_mutex_);
  std::uint64_t dropped = 0;
  for (const auto& ring : rings_) dropped += ring->dropped();
  return dropped;
}

void CanTrafficLog::write_out(const char* data, std::size_t size) {
  while (size > 0 && error_.empty()) {
    const ssize_t written = ::write(file_, data, size);
    if (written < 0) {
      if (errno == EINTR) continue;
      error_ = "writing the CAN log '" + path_ + "' failed: " + std::strerror(errno);
      return;
    }
    data += written;
    size -= static_cast<std::size_t>(written);
  }
}

std::size_t CanTrafficLog::drain() {
  const std::lock_guard lock(rings_mutex_);
  std::size_t drained = 0;
  for (const auto& ring : rings_) {
    drained += ring->pop_all([&](const Ring::Record& record) {
      if (buffered_ + kMaxCandumpLineChars > buffer_.size()) {
        write_out(buffer_.data(), buffered_);
        buffered_ = 0;
      }
      buffered_ += format_candump_line(record.wall_time_ns / 1000, ring->interface(), record.frame,
                                       std::span(buffer_).subspan(buffered_));
      if (error_.empty()) ++written_;
    });
  }
  if (buffered_ > 0) {
    write_out(buffer_.data(), buffered_);
    buffered_ = 0;
  }
  return drained;
}

void CanTrafficLog::writer_loop() {
  for (;;) {
    const bool stopping = stop_.load(std::memory_order_acquire);
    // After the stop request, one more full drain picks up everything recorded before it.
    if (drain() == 0 && stopping) return;
    if (!stopping) std::this_thread::sleep_for(kWriterIdle);
  }
}

CanLogReport CanTrafficLog::close() {
  if (closed_) return report_;
  finish();
  if (!staging_path_.empty()) {
    if (::rename(staging_path_.c_str(), path_.c_str()) < 0 && error_.empty()) {
      error_ = "putting the CAN log '" + path_ + "' in place failed: " + std::strerror(errno);
    }
  }
  report_.error = error_;
  return report_;
}

CanLogReport CanTrafficLog::abandon() {
  if (closed_) return report_;
  finish();
  if (!staging_path_.empty()) {
    const std::string beside = path_ + ".incomplete";
    if (::rename(staging_path_.c_str(), beside.c_str()) == 0) {
      report_.abandoned_path = beside;
    } else {
      report_.abandoned_path = staging_path_;
    }
  }
  return report_;
}

void CanTrafficLog::finish() {
  {
    const std::lock_guard lock(rings_mutex_);
    closed_ = true;
    for (const auto& ring : rings_) ring->close();
  }
  stop_.store(true, std::memory_order_release);
  if (writer_.joinable()) writer_.join();
  // Records lost after a write error were formatted but never reached the file.
  if (::close(file_) < 0 && error_.empty()) {
    error_ = "closing the CAN log '" + path_ + "' failed: " + std::strerror(errno);
  }
  file_ = -1;
  report_.records_written = written_;
  report_.records_dropped = records_dropped();
  report_.error = error_;
}

LoggingCanBus::LoggingCanBus(std::unique_ptr<hal::CanBus> bus, CanTrafficLog& log)
    : bus_(std::move(bus)),
      ring_(log.add_ring(bus_->name())),
      stamps_on_monotonic_(log.stamps_on_monotonic_) {}

LoggingCanBus::~LoggingCanBus() = default;

hal::Status LoggingCanBus::send(const hal::CanFrame& frame) {
  const hal::Status status = bus_->send(frame);
  if (status == hal::Status::kOk) ring_->push(frame, clock_ns(CLOCK_REALTIME));
  return status;
}

std::size_t LoggingCanBus::send_batch(std::span<const hal::CanFrame> frames) {
  const std::size_t sent = bus_->send_batch(frames);
  const std::int64_t now_ns = clock_ns(CLOCK_REALTIME);
  for (std::size_t i = 0; i < sent; ++i) ring_->push(frames[i], now_ns);
  return sent;
}

hal::Status LoggingCanBus::receive(hal::CanFrame& out) {
  const hal::Status status = bus_->receive(out);
  if (status == hal::Status::kOk) {
    const std::int64_t now_realtime_ns = clock_ns(CLOCK_REALTIME);
    std::int64_t wall_ns = now_realtime_ns;
    if (stamps_on_monotonic_ && out.stamp_ns != 0) {
      wall_ns = out.stamp_ns + (now_realtime_ns - clock_ns(CLOCK_MONOTONIC));
    }
    ring_->push(out, wall_ns);
  }
  return status;
}

}  // namespace cambio::can
