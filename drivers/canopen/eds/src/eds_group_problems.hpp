#pragma once

// The parts of check_eds_for_group (eds_group_check.cpp) and the list they report into.

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "cambio/canopen/eds/eds_group_check.hpp"

namespace cambio::canopen::eds {

/// Adds problems about some joints to a report, naming each object as the EDS does; the same
/// problem for another joint adds the joint to it.
class ProblemContext {
 public:
  ProblemContext(const EdsFile& eds, std::string joint, EdsGroupReport& report)
      : ProblemContext(eds, std::vector<std::string>{std::move(joint)}, report) {}
  ProblemContext(const EdsFile& eds, std::vector<std::string> joints, EdsGroupReport& report)
      : eds_(eds), joints_(std::move(joints)), report_(report) {}

  const EdsFile& eds() const { return eds_; }
  void add(ObjectAddress object, std::string problem, std::string change);
  void note(std::string text);

 private:
  const EdsFile& eds_;
  std::vector<std::string> joints_;
  EdsGroupReport& report_;
};

/// "6502" (an EDS section's name).
std::string index_text(std::uint16_t index);

/// 0x1000's DefaultValue, when given, is a CiA 402 device (the master refuses others).
void check_device_type(const CanGroupView& view, std::size_t joint, ProblemContext& context);

/// 0x6502's DefaultValue, when given, supports the joint's command mode.
void check_drive_modes(const CanGroupView& view, std::size_t joint, ProblemContext& context);

/// The PDO layout against the drive's PDO count, mapping capacity and mappable objects;
/// `used` collects the objects mapped.
void check_pdo_layout(const CanGroupView& view, std::size_t joint, ProblemContext& context,
                      std::set<std::pair<std::uint16_t, std::uint8_t>>& used);

}  // namespace cambio::canopen::eds
