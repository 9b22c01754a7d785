#pragma once

#include <string>
#include <vector>

namespace cambio::hal {

/// What a backend whose cameras can fail (a real camera unplugged mid-run) offers the run's
/// report (Backend::offer): the faults its cameras latched, one sentence each naming the camera
/// and its device. A faulted camera's grab() returns Status::kFault from then on. Read after the
/// loops stopped; not real-time safe.
class CameraFaults {
 public:
  virtual ~CameraFaults() = default;
  virtual std::vector<std::string> camera_faults() const = 0;
};

}  // namespace cambio::hal
