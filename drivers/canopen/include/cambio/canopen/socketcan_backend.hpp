#pragma once

// The "socketcan" backend (hal::Backend): the rig's joint groups whose backend is "socketcan",
// as CiA 402 drives on CAN buses, with this process as the CANopen master and each group the SYNC
// producer of its own bus. Lifecycle:
//   make_joint_group()  opens the group's bus (once) with the injected opener
//   configure()         per bus: NMT reset communication, wait for each node's boot-up (or its
//                       answer to an SDO read of 0x1000), write the drive parameters and PDO
//                       mappings over SDO and read them back (a mismatch refuses to go on, naming
//                       node, object, value written and value read), read the rated torque when
//                       effort is fed forward or fed back, read each drive's state and position,
//                       NMT start; the writes are kept for replaying on a drive that reboots
//   activate()          the joints whose rig sets `homing` home (homing.hpp), one after the
//                       other, each failure naming node and joint; then heartbeat and SYNC-answer
//                       watching starts; drives are enabled by the joint loop's requests, at their
//                       measured positions
//   deactivate()        quick stop, then disable every drive, then NMT enter pre-operational
//                       (also on SIGINT); noexcept, idempotent. Called once the loops stopped.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cambio/canopen/bus_pump.hpp"
#include "cambio/canopen/can_joint_group.hpp"
#include "cambio/canopen/can_rig.hpp"
#include "cambio/canopen/can_rig_check.hpp"
#include "cambio/hal/backend_factory.hpp"

namespace cambio::canopen {

/// Opens the kernel interface a rig's bus names (the application passes SocketCanBus::open; unit
/// tests an in-process endpoint). Throws std::runtime_error with a clear message.
using BusOpener = std::function<std::unique_ptr<hal::CanBus>(const CanBusInfo&)>;

struct SocketCanBackendOptions {
  /// The SYNC rate of a group that sets none (JointGroupInfo::rate_hz == 0): the rig's
  /// loops.joint.rate_hz, which HardwareInfo does not carry.
  double default_joint_rate_hz = 1000.0;
  /// How long configure() waits for the boot-ups after NMT reset communication.
  double boot_timeout_s = 2.0;
  /// How configure() waits for frames (default: hal::CanBus::wait_for_frame).
  BusPump::Waiter waiter;
};

class SocketCanBackend final : public hal::Backend {
 public:
  static constexpr const char* kName = "socketcan";

  /// `can_rig` is the rig's CANopen side: the groups' buses and settings, the joints' drives.
  SocketCanBackend(const hal::HardwareInfo& hardware, CanRigInfo can_rig,
                   const hal::BackendContext& context, BusOpener opener,
                   SocketCanBackendOptions options = {});
  ~SocketCanBackend() override;

  std::unique_ptr<hal::JointGroup> make_joint_group(std::string_view group_name) override;
  std::unique_ptr<hal::Camera> make_camera(std::string_view camera_name) override;
  std::unique_ptr<hal::TouchSensor> make_touch_sensor(std::string_view sensor_name) override;
  void configure() override;
  void activate() override;
  void deactivate() noexcept override;
  std::vector<hal::BackendLoop> loops() override { return {}; }
  /// Each CanJointGroup made (const: its counters, for the run's report).
  void offer(hal::BackendOffers& offers) override;

  /// The group made for `group_name` (for its counters), or nullptr.
  const CanJointGroup* group(std::string_view group_name) const;

 private:
  struct Bus {
    CanBusInfo info;
    std::unique_ptr<hal::CanBus> bus;
    std::string group;  ///< The one group whose SYNC drives this bus.
  };
  void configure_group(CanJointGroup& group, const hal::JointGroupInfo& info);
  void home_group(CanJointGroup& group, const hal::JointGroupInfo& info);

  hal::HardwareInfo hardware_;
  CanRigInfo can_rig_;
  hal::Clock& clock_;
  BusOpener opener_;
  SocketCanBackendOptions options_;
  std::map<std::string, Bus, std::less<>> buses_;
  std::map<std::string, std::unique_ptr<CanJointGroup>, std::less<>> groups_;
  bool configured_ = false;
  bool active_ = false;
};

/// Registers the "socketcan" backend with `factory` for a rig whose CANopen side is `can_rig`:
/// it drives real devices, so a run using it is paced by the wall clock; its check
/// (check_can_rig) refuses buses, node ids and bus loads that cannot work.
void register_socketcan_backend(hal::BackendFactory& factory, CanRigInfo can_rig, BusOpener opener,
                                SocketCanBackendOptions options = {});

}  // namespace cambio::canopen
