#pragma once

#include <string>

#include "cambio/hal/touch_sensor.hpp"
#include "cambio/sim/physics_loop.hpp"

namespace cambio::sim {

/// A hand's touch sensor: MuJoCo's broad phase (bounding volumes, the paper's "bubble") and
/// narrow phase (exact geometry) find the contacts; the physics loop sums those on the end
/// effector each step. read() is real-time safe.
class SimTouchSensor final : public hal::TouchSensor {
 public:
  explicit SimTouchSensor(TouchLink& link) : link_(link) {}
  const std::string& name() const override { return link_.name; }
  hal::Status read(hal::TouchReading& out) override {
    // A read that keeps meeting the physics loop mid-write gives up: the last good reading
    // stands, its stamp telling how old it is.
    (void)link_.reading.read(last_);
    out = last_;
    return hal::Status::kOk;
  }

 private:
  TouchLink& link_;
  hal::TouchReading last_;
};

}  // namespace cambio::sim
