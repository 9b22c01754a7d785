#pragma once

// Whether a vendor's drive, as its EDS describes it, can be one of a CAN joint group's drives:
// every object the master reads or writes over SDO exists with a fitting size and access, the
// values it writes are within the object's LowLimit..HighLimit, every object the PDO layout maps
// is mappable with the mapped size, the layout fits the drive's PDO count and mapping capacity,
// the heartbeat can be produced, and 0x6502 lists the group's command mode. The list of objects
// comes from the master's functions (eds_group_needs.hpp), never from a copy of it.

#include <optional>
#include <string>
#include <vector>

#include "cambio/canopen/eds/eds_file.hpp"
#include "cambio/canopen/eds/eds_group_needs.hpp"

namespace cambio::canopen::eds {

/// One way the drive does not fit the group.
struct EdsProblem {
  ObjectAddress object;
  std::string object_name;          ///< The EDS's ParameterName, or the master's when absent.
  int line = 0;                     ///< The object's line in the EDS; 0 when absent.
  std::vector<std::string> joints;  ///< The joints it concerns (every one alike).
  std::string problem;              ///< What does not fit, with the values.
  std::string change;               ///< What to change: the rig key, or the drive.

  /// "0x1017:00 Producer heartbeat time (line 120), joints pan, tilt: ...; change ...".
  std::string to_string() const;
};

struct EdsGroupReport {
  std::vector<EdsProblem> problems;
  std::vector<std::string> notes;  ///< What could not be checked, and why.
  std::vector<std::string> joints_checked;
  int objects_checked = 0;  ///< Distinct objects the master uses, over the joints checked.

  bool fits() const { return problems.empty(); }
};

/// Checks `eds` for the joints of `view` whose drive has node id `node_id` (every joint when
/// nullopt); $NODEID in the EDS is each joint's node id. Throws std::invalid_argument when the
/// rig's values do not fit the master's objects at all (as configure would).
EdsGroupReport check_eds_for_group(const EdsFile& eds, const CanGroupView& view,
                                   std::optional<int> node_id = std::nullopt);

}  // namespace cambio::canopen::eds
