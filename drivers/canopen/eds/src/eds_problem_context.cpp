#include <algorithm>
#include <array>

#include "cambio/canopen/cia402.hpp"
#include "eds_group_problems.hpp"

namespace cambio::canopen::eds {

namespace {

/// CiA 402-2 §8.4.5 (0x6502): bit n-1 set when mode n is supported, for the standard modes.
struct DriveMode {
  int mode;
  std::string_view name;
};
constexpr std::array<DriveMode, 9> kModes = {{{1, "PP"},
                                              {2, "VL"},
                                              {3, "PV"},
                                              {4, "TQ"},
                                              {6, "HM"},
                                              {7, "IP"},
                                              {8, "CSP"},
                                              {9, "CSV"},
                                              {10, "CST"}}};

bool supports(std::int64_t modes, int mode) {
  return ((static_cast<std::uint64_t>(modes) >> (mode - 1)) & 1u) != 0;
}

std::string mode_text(int mode) {
  for (const DriveMode& known : kModes) {
    if (known.mode == mode) return std::string(known.name) + " (" + std::to_string(mode) + ")";
  }
  return std::to_string(mode);
}

}  // namespace

std::string index_text(std::uint16_t index) {
  constexpr std::string_view kDigits = "0123456789ABCDEF";
  std::string text(4, '0');
  for (int i = 0; i < 4; ++i)
    text[static_cast<std::size_t>(3 - i)] = kDigits[(index >> (4 * i)) & 0xF];
  return text;
}

void ProblemContext::add(ObjectAddress object, std::string problem, std::string change) {
  for (EdsProblem& known : report_.problems) {
    if (known.object == object && known.problem == problem && known.change == change) {
      for (const std::string& joint : joints_) {
        if (std::find(known.joints.begin(), known.joints.end(), joint) == known.joints.end()) {
          known.joints.push_back(joint);
        }
      }
      return;
    }
  }
  EdsProblem added{object, "(not in the EDS)", 0, joints_, std::move(problem), std::move(change)};
  if (const EdsEntry* entry = eds_.find(object)) {
    added.object_name = entry->name;
    added.line = entry->line;
  } else if (const EdsObject* parent = eds_.find(object.index)) {
    added.object_name = parent->name;
    added.line = parent->line;
  }
  report_.problems.push_back(std::move(added));
}

void ProblemContext::note(std::string text) {
  if (std::find(report_.notes.begin(), report_.notes.end(), text) == report_.notes.end()) {
    report_.notes.push_back(std::move(text));
  }
}

void check_device_type(const CanGroupView& view, std::size_t joint, ProblemContext& context) {
  const EdsEntry* entry = context.eds().find(ObjectAddress{kDeviceType, 0});
  if (entry == nullptr || !entry->default_value) return;
  const std::int64_t value = entry->default_value->evaluate(view.drives[joint].node_id);
  if ((value & 0xFFFF) != (cia402::kDeviceTypeServoDrive & 0xFFFF)) {
    context.add({kDeviceType, 0},
                "DefaultValue " + entry->default_text +
                    " is not a CiA 402 drive (profile 402 = 0x0192 in the low 16 bits); the "
                    "master refuses it",
                "use a CiA 402 drive");
  }
}

void check_drive_modes(const CanGroupView& view, std::size_t joint, ProblemContext& context) {
  const EdsEntry* entry = context.eds().find(cia402::kSupportedDriveModes);
  if (entry == nullptr || !entry->default_value) {
    context.note("0x6502:00 (supported drive modes) " +
                 std::string(entry == nullptr ? "is not in the EDS" : "has no DefaultValue") +
                 ": the command mode was not checked against it");
    return;
  }
  const std::int64_t modes = entry->default_value->evaluate(view.drives[joint].node_id);
  const bool position = view.drives[joint].mode == hal::CommandMode::kPosition;
  const auto wanted = static_cast<int>(position ? cia402::Mode::kCyclicSynchronousPosition
                                                : cia402::Mode::kCyclicSynchronousVelocity);
  if (supports(modes, wanted)) return;
  const int other = static_cast<int>(position ? cia402::Mode::kCyclicSynchronousVelocity
                                              : cia402::Mode::kCyclicSynchronousPosition);
  std::string listed;
  for (const DriveMode& known : kModes) {
    if (supports(modes, known.mode)) listed += (listed.empty() ? "" : ", ") + mode_text(known.mode);
  }
  const std::string key = "joints." + view.joints[joint].name + ".servo.command";
  context.add(cia402::kSupportedDriveModes,
              "DefaultValue " + entry->default_text + " lists " +
                  (listed.empty() ? std::string("no standard mode") : listed) + ", not " +
                  mode_text(wanted) + " that the group commands",
              supports(modes, other)
                  ? "set " + key + " to " + (position ? "velocity" : "position") + " (" +
                        mode_text(other) + ") for every joint of group " + view.group.name
                  : "use a drive that supports CSP (8) or CSV (9)");
}

}  // namespace cambio::canopen::eds
