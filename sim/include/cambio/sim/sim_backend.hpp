#pragma once

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "cambio/config/rig_config.hpp"
#include "cambio/config/scene_config.hpp"
#include "cambio/hal/backend_factory.hpp"
#include "cambio/hal/hardware_info.hpp"
#include "cambio/sim/ground_truth.hpp"
#include "cambio/sim/mjcf_builder.hpp"
#include "cambio/sim/physics_loop.hpp"
#include "cambio/sim/rendered_views.hpp"
#include "cambio/sim/renderer.hpp"
#include "cambio/sim/world.hpp"

namespace cambio::sim {

class CameraFrames;

/// Registers the "sim" backend: the rig's sim groups, cameras and touch sensors served by one
/// MuJoCo world built from `rig` and `scene` (what only the sim needs reaches it through this
/// maker, which the application builds from the experiment; the factory supplies the hardware
/// description and the run's clock and seed).
void register_sim_backend(hal::BackendFactory& factory, const config::RigConfig& rig,
                          config::SceneConfig scene);

/// The simulator behind the HAL. One world, one physics loop (run it at the rate loops()
/// reports), one renderer shared by the cameras (created with the first camera or ground-truth
/// render, so a physics-only run needs no GL). Every reading and image is stamped on the run's
/// clock (BackendContext::clock): the physics loop stamps with its tick's time.
///
/// The world holds every joint of the rig, whichever backend drives its group. The sim makes
/// joint groups only for groups on `backend: sim`; a group another backend drives can be
/// followed (follow_group), so the sim's cameras and touch sensors see what those drives did.
///
/// Each sim joint has a CiA 402 drive (see PhysicsLoop): it starts switch-on disabled and
/// executes commands only once the joint loop has requested kEnable and it reached operation
/// enabled. inject_fault(), inject_comm_loss() and freeze_feedback() make a drive misbehave so
/// the layers above are tested without CAN.
class SimBackend final : public hal::Backend {
 public:
  static constexpr const char* kName = "sim";

  /// Builds the world (may throw ConfigError, MujocoError, std::runtime_error).
  /// `hardware` must describe `rig` (config::hardware_description(rig)); `context.clock` must be
  /// set and outlive the backend (std::invalid_argument otherwise). Tests build one directly
  /// this way; applications through register_sim_backend().
  SimBackend(const config::RigConfig& rig, const config::SceneConfig& scene,
             const hal::HardwareInfo& hardware, const hal::BackendContext& context,
             const MjcfOptions& mjcf_options = {});
  ~SimBackend() override;

  /// Throws hal::BackendUnavailable for a group another backend drives (or that the sim follows)
  /// and std::runtime_error for an unknown group or one made twice. Before activate().
  std::unique_ptr<hal::JointGroup> make_joint_group(std::string_view group_name) override;
  std::unique_ptr<hal::Camera> make_camera(std::string_view camera_name) override;
  /// Before activate().
  std::unique_ptr<hal::TouchSensor> make_touch_sensor(std::string_view sensor_name) override;
  /// The world's joints of `group` follow the positions `leader` reports: kinematic joints are
  /// set to them, physics joints take them as their PD reference. Refuses (BackendUnavailable) a
  /// group the sim drives itself or made, an unknown group, or one with an unknown joint.
  /// Before activate().
  void follow_group(const hal::JointGroupInfo& group, const hal::JointStateSource& leader) override;

  /// Checks the devices made: every camera and touch sensor must hang from joints the sim
  /// drives or follows (a joint no one moves would show a frozen view). Throws
  /// std::runtime_error naming the device, the joint and its group.
  void configure() override;
  /// Boots the drives (switch-on disabled) and publishes the first readings and world state.
  void activate() override;
  /// Quick stop and disable every drive at once (faulted drives stay faulted) and publish the
  /// readings that say so. Call it once the physics loop is no longer running (after the
  /// executor stopped). Idempotent.
  void deactivate() noexcept override;
  std::vector<hal::BackendLoop> loops() override;
  /// The sim models the whole robot: it follows every group another backend drives.
  bool follows_other_backends() const override { return true; }
  /// Its GroundTruth (evaluation) and its RenderedViews (the report's renderer, whole frames of
  /// foveated eyes).
  void offer(hal::BackendOffers& offers) override;

  /// Test hooks, for testing the layers above without CAN. Each takes effect at the next physics
  /// step; thread-safe, lock-free, no allocation. Throw std::invalid_argument for a joint that
  /// is not in a sim group.
  ///
  /// The joint's drive latches a fault with the CiA 301/402 emergency code (not 0): fault
  /// reaction (brakes like a quick stop), then kFault; its readings carry kJointFault and the
  /// code until a kFaultReset request.
  void inject_fault(std::string_view joint_name, std::uint16_t emcy_error_code);
  /// The joint's drive loses its master: its reading freezes (stamp included) and carries
  /// kJointCommLost until a kFaultReset request, and the drive runs its fault reaction with
  /// error kCommLossErrorCode (what a drive whose abort-connection option is "fault" does).
  void inject_comm_loss(std::string_view joint_name);
  /// While `frozen`, the joint's reading stops updating (its stamp too) and nothing flags it:
  /// the joint loop must see the stale stamp. The drive runs on.
  void freeze_feedback(std::string_view joint_name, bool frozen);

  /// Evaluation only (tests, `cambio render`, experiment scoring); never hand it to control or
  /// perception.
  GroundTruth& ground_truth();
  World& world() { return *world_; }
  PhysicsLoop& physics() { return *physics_; }
  /// Hold a Renderer::Lease while using it directly. Makes the renderer if no camera or
  /// ground-truth render has yet.
  Renderer& renderer();
  /// The renderer if a camera or a ground-truth render made it, else null (a physics-only run
  /// opens no GL context).
  const Renderer* renderer_if_made() const { return renderer_.get(); }

 private:
  /// Index into World::joints() of a joint in a sim group, else std::invalid_argument.
  int sim_joint(std::string_view joint_name) const;
  /// Throws unless every joint from `link` up to the base is driven or followed by the sim.
  void check_moved_by_sim(std::string_view device, const std::string& link) const;

  config::RigConfig rig_;
  hal::HardwareInfo hardware_;
  std::uint64_t seed_ = 0;
  std::unique_ptr<World> world_;
  std::unique_ptr<PhysicsLoop> physics_;
  std::unique_ptr<Renderer> renderer_;
  std::unique_ptr<CameraFrames> camera_frames_;
  std::unique_ptr<GroundTruth> ground_truth_;
  std::unique_ptr<RenderedViews> rendered_views_;
  std::set<std::string, std::less<>> made_groups_;
  std::set<std::string, std::less<>> followed_groups_;
  std::set<std::string, std::less<>> made_cameras_;
  std::set<std::string, std::less<>> made_touch_sensors_;
  std::uint64_t camera_streams_ = 0;
};

}  // namespace cambio::sim
