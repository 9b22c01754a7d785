#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>

#include "cambio/hal/joint_group.hpp"
#include "cambio/hal/seqlock_channel.hpp"

namespace cambio::hal {

/// The newest readings of a joint group, readable from any thread without touching the group
/// (whose calls belong to the joint loop's thread).
class JointStateSource {
 public:
  /// Most joints one source carries.
  static constexpr std::size_t kMaxJoints = 32;

  virtual ~JointStateSource() = default;
  /// Copies the newest readings into `out` (size == the group's joint count). False if none was
  /// published yet, the size is wrong, or a concurrent publish kept every attempt torn (out is
  /// then untouched). Thread-safe; real-time safe.
  virtual bool latest(std::span<JointState> out) const noexcept = 0;
};

/// Wraps a joint group and republishes what every read() returned, so another backend can follow
/// the group from its own thread (the sim's head following CAN drives). Forwards every call
/// unchanged; adds one seqlock write per read(). Real-time safe.
class JointStateTap final : public JointGroup, public JointStateSource {
 public:
  /// `inner` must outlive the tap and have at most kMaxJoints joints.
  explicit JointStateTap(JointGroup& inner) : inner_(inner) {}

  const JointGroupInfo& info() const override { return inner_.info(); }

  Status read(std::span<JointState> out, std::int64_t& stamp_ns) override {
    const Status status = inner_.read(out, stamp_ns);
    if (status != Status::kRejected && out.size() <= kMaxJoints) {
      Readings readings;
      readings.count = static_cast<std::uint32_t>(out.size());
      std::copy(out.begin(), out.end(), readings.states.begin());
      readings_.write(readings);
    }
    return status;
  }
  Status write(std::span<const JointCommand> commands) override { return inner_.write(commands); }
  Status request(DriveRequest request, int joint) override {
    return inner_.request(request, joint);
  }
  Status sync() override { return inner_.sync(); }

  bool latest(std::span<JointState> out) const noexcept override {
    Readings readings;
    if (readings_.version() == 0 || !readings_.read(readings)) return false;
    if (readings.count != out.size()) return false;
    std::copy_n(readings.states.begin(), out.size(), out.begin());
    return true;
  }

 private:
  struct Readings {
    std::array<JointState, kMaxJoints> states{};
    std::uint32_t count = 0;
  };
  JointGroup& inner_;
  SeqlockChannel<Readings> readings_;
};

}  // namespace cambio::hal
