#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "cambio/hal/image.hpp"
#include "cambio/hal/triple_buffer.hpp"
#include "cambio/sim/renderer.hpp"
#include "cambio/sim/world.hpp"
#include "cambio/sim/world_snapshot.hpp"

namespace cambio::sim {

/// The first scene surface a ray meets (GroundTruth::cast_ray).
struct RayHit {
  bool hit = false;
  /// Along the ray from its origin (m); infinity when nothing was hit.
  double distance_m = std::numeric_limits<double>::infinity();
  /// Where it hit, in the world (NaN when nothing was hit).
  Eigen::Vector3d p_W = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  /// The scene object hit; for scene geometry that is no object (the floor) the geom's name;
  /// empty when nothing was hit.
  std::string object;
};

/// The world's true state, for tests and evaluation only: control and perception never see it
/// (it is not part of the HAL). Reads the newest snapshot the physics loop published. Not
/// real-time safe; thread-safe against the loops (each call takes the snapshot it reads) and
/// between evaluation threads.
class GroundTruth {
 public:
  GroundTruth(const World& world, hal::TripleBuffer<WorldSnapshot>& truth_snapshots);
  ~GroundTruth();

  /// Takes the newest published snapshot (every query below calls it).
  void refresh();
  std::int64_t stamp_ns();
  std::uint64_t step();
  /// True angle of a rig joint (rad). Throws std::out_of_range for an unknown joint.
  double joint_position_rad(const std::string& joint_name);
  /// Pose of a camera's optical frame (OpenCV: z forward, x right, y down) in the world.
  Eigen::Isometry3d X_WC(const std::string& camera_name);
  /// Pose of a scene object's frame in the world.
  Eigen::Isometry3d X_WO(const std::string& object_name);
  /// Pose of a link (a joint's moving body, or "base") in the world.
  Eigen::Isometry3d X_WL(const std::string& link_name);

  /// The first scene surface (objects, the floor) a ray from `p_W` along `direction_W` (any
  /// non-zero length) meets. The robot's own bodies (arms, torso, head) and the eyes' sky planes
  /// are not scene: an eye looking at an object "through" the robot's hand sees the object.
  /// `ignore_object` names a scene object (or scene geometry, as RayHit::object names it) the
  /// ray passes through (empty: none). Throws
  /// std::invalid_argument for a zero or non-finite direction, std::out_of_range for an unknown
  /// `ignore_object`.
  RayHit cast_ray(const Eigen::Vector3d& p_W, const Eigen::Vector3d& direction_W,
                  std::string_view ignore_object = {});
  /// What blocks the segment from `p_from_W` to `p_to_W` (occlusion): the first scene surface
  /// the segment meets before `tolerance_m` short of `p_to_W`, passing through `ignore_object`
  /// (usually the object `p_to_W` lies on, so a point on its surface does not occlude itself).
  /// hit == false when the view is clear.
  RayHit segment_blocker(const Eigen::Vector3d& p_from_W, const Eigen::Vector3d& p_to_W,
                         std::string_view ignore_object = {}, double tolerance_m = 1e-3);

  /// Signed distance from `p_W` to the surface of a scene object (m): positive outside, negative
  /// inside, the nearest of the object's geoms (spheres, boxes, cylinders, capsules; an
  /// ellipsoid by its largest radius). Throws std::out_of_range for an unknown object,
  /// std::invalid_argument for a geom of another shape.
  double distance_to_object_m(const std::string& object_name, const Eigen::Vector3d& p_W);
  /// The gap between a touch sensor's end effector (World::end_effector_bodies of `link_name`:
  /// what the sensor feels) and a scene object (m): the smallest signed distance from its
  /// colliding geometry to the object's surface and back, boxes sampled along their edges,
  /// capsules and cylinders along their axis less the radius, spheres at their centre less the
  /// radius (within an eighth of a box edge where two edges cross); negative when they overlap
  /// (a contact's depth). Throws std::out_of_range for an unknown link or object.
  double end_effector_gap_m(const std::string& link_name, const std::string& object_name);

  /// Renders a view of the newest state: a rig camera at its intrinsics (width, height 0) or
  /// any MuJoCo camera (the overview) at the given size. Writes top-row-first RGB into `rgb`
  /// (resized if needed, stamped with the state's time) and, if `depth_m` is given, metric depth
  /// along the optical axis. Needs the renderer (set_renderer_provider()); waits while a camera
  /// holds it, and a camera that finds it held here skips that grab.
  void render(const std::string& camera_name, int width_px, int height_px, const ViewOptions& view,
              hal::Image& rgb, std::vector<float>* depth_m);

  /// What a rig camera's image shows of the newest state: render() at its intrinsics, through its
  /// lens when its rig entry has one (as the camera renders, SimLens). For pictures of what an
  /// eye saw (a run's key frames); metric uses take render()'s pinhole view.
  void render_as_seen(const std::string& camera_name, hal::Image& rgb);

  /// Where render() gets the renderer (built on first use, so physics-only users need no GL).
  void set_renderer_provider(std::function<Renderer&()> provider) {
    renderer_provider_ = std::move(provider);
  }

 private:
  int object_body(const std::string& object_name) const;

  const World& world_;
  hal::TripleBuffer<WorldSnapshot>& snapshots_;
  std::mutex mutex_;  ///< Evaluation threads only; no loop takes it.
  mjData_* data_ = nullptr;
  WorldSnapshot current_;  ///< The snapshot data_ shows (the world at construction until one).
  std::function<Renderer&()> renderer_provider_;
  std::vector<std::uint8_t> rgb_bottom_up_;
  std::vector<float> depth_bottom_up_;
  std::map<std::string, std::shared_ptr<const class SimLens>> lenses_;  ///< By camera, on use.
};

}  // namespace cambio::sim
