// Scene files (scenes/*.yaml): the objects around the robot. Read with MapReader so every
// problem is reported at once with file:line:col.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "cambio/config/scene_config.hpp"

namespace cambio::config {

namespace {

std::array<double, 3> read_rgb(MapReader& map, std::string_view key,
                               std::array<double, 3> fallback) {
  return map.vector3_or(key, fallback, Range::closed(0.0, 1.0));
}

TextureConfig read_texture(MapReader map, TextureConfig fallback) {
  TextureConfig texture = fallback;
  const std::string type =
      map.choice("type", {"none", "checker", "noise", "stripes", "dots", "chessboard"});
  if (type == "none") texture.kind = TextureKind::kNone;
  if (type == "checker") texture.kind = TextureKind::kChecker;
  if (type == "noise") texture.kind = TextureKind::kNoise;
  if (type == "stripes") texture.kind = TextureKind::kStripes;
  if (type == "dots") texture.kind = TextureKind::kDots;
  if (type == "chessboard") {
    texture.kind = TextureKind::kChessboard;
    const std::vector<double> squares = map.numbers("squares", Range::closed(2.0, 64.0));
    const bool whole = squares.size() == 2 && squares[0] == std::floor(squares[0]) &&
                       squares[1] == std::floor(squares[1]);
    if (!whole) {
      map.error("squares", "a chessboard needs [across, down]: two whole numbers of squares");
    } else {
      texture.squares = {static_cast<int>(squares[0]), static_cast<int>(squares[1])};
    }
  }
  texture.feature_size_m =
      map.number_or("feature_size_m", fallback.feature_size_m, Range::positive());
  texture.second_rgb = read_rgb(map, "second_rgb", fallback.second_rgb);
  texture.pattern_seed = static_cast<std::uint64_t>(map.integer_or(
      "seed", static_cast<std::int64_t>(fallback.pattern_seed), Range::non_negative()));
  map.finish();
  return texture;
}

/// A chessboard is drawn on each face of a box's cube texture, one face of which spans the
/// box's largest extent: on a box whose two largest sizes are equal, the face the board is seen
/// on is that square, and the squares are feature_size_m wide.
void check_chessboard_object(MapReader& map, const SceneObjectConfig& object) {
  std::array<double, 3> sizes = object.size_m;
  std::sort(sizes.begin(), sizes.end());
  if (object.shape != ShapeKind::kBox || std::abs(sizes[2] - sizes[1]) > 1e-9 * sizes[2]) {
    map.error("texture",
              "a chessboard goes on a box with a square face (its two largest sizes equal), "
              "where its squares are square");
    return;
  }
  const auto& texture = object.texture;
  const double across_m = texture.squares[0] * texture.feature_size_m;
  const double down_m = texture.squares[1] * texture.feature_size_m;
  if (std::max(across_m, down_m) > sizes[2] + 1e-12) {
    map.error("texture", "the board (" + std::to_string(across_m) + " x " + std::to_string(down_m) +
                             " m) is larger than the box's face (" + std::to_string(sizes[2]) +
                             " m)");
  }
}

std::array<double, 3> normalised(MapReader& map, std::string_view key, std::array<double, 3> v) {
  const double norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (norm < 1e-9) {
    map.error(key, "must be a non-zero vector");
    return {0.0, 0.0, 1.0};
  }
  return {v[0] / norm, v[1] / norm, v[2] / norm};
}

MotionConfig read_motion(MapReader map) {
  MotionConfig motion;
  const std::string type = map.choice("type", {"waypoints", "oscillate", "circle"});
  motion.start_s = map.number_or("start_s", 0.0, Range::non_negative());
  if (type == "waypoints") {
    motion.kind = MotionKind::kWaypoints;
    double previous_s = -1.0;
    for (auto& point_map : map.map_list("waypoints")) {
      Waypoint point;
      point.time_s = point_map.number("time_s", Range::non_negative());
      point.xyz_m = point_map.vector3("xyz_m");
      if (point.time_s <= previous_s) {
        point_map.error("time_s", "waypoint times must increase (" + std::to_string(point.time_s) +
                                      " follows " + std::to_string(previous_s) + ")");
      }
      previous_s = point.time_s;
      point_map.finish();
      motion.waypoints.push_back(point);
    }
    if (motion.waypoints.empty()) map.error("waypoints", "needs at least one waypoint");
  } else if (type == "oscillate") {
    motion.kind = MotionKind::kOscillate;
    motion.axis = normalised(map, "axis", map.vector3_or("axis", {0.0, 1.0, 0.0}));
    motion.amplitude_m = map.number("amplitude_m", Range::positive());
    motion.period_s = map.number("period_s", Range::positive());
  } else if (type == "circle") {
    motion.kind = MotionKind::kCircle;
    motion.axis = normalised(map, "axis", map.vector3_or("axis", {0.0, 0.0, 1.0}));
    motion.radius_m = map.number("radius_m", Range::positive());
    motion.period_s = map.number("period_s", Range::positive());
  }
  map.finish();
  return motion;
}

SceneObjectConfig read_object(MapReader map) {
  SceneObjectConfig object;
  object.name = map.text("name");
  const std::string shape = map.choice("shape", {"sphere", "box", "cylinder", "capsule", "plane"});
  // The size keys depend on the shape; a key that does not fit is reported, not ignored.
  const auto refuse = [&map, &shape](std::string_view key) {
    if (map.has(key)) map.error(key, "does not apply to a " + shape);
  };
  if (shape == "sphere") {
    object.shape = ShapeKind::kSphere;
    const double radius = map.number("radius_m", Range::positive());
    object.size_m = {2.0 * radius, 2.0 * radius, 2.0 * radius};
    refuse("size_m");
    refuse("length_m");
  } else if (shape == "box") {
    object.shape = ShapeKind::kBox;
    object.size_m = map.vector3("size_m", Range::positive());
    refuse("radius_m");
    refuse("length_m");
  } else if (shape == "cylinder" || shape == "capsule") {
    object.shape = shape == "cylinder" ? ShapeKind::kCylinder : ShapeKind::kCapsule;
    const double radius = map.number("radius_m", Range::positive());
    const double length = map.number("length_m", Range::positive());
    object.size_m = {2.0 * radius, 2.0 * radius, length};
    refuse("size_m");
  } else if (shape == "plane") {
    object.shape = ShapeKind::kPlane;
    const auto size = map.numbers("size_m", Range::positive());
    if (size.size() != 2) {
      map.error("size_m", "a plane needs [x, y] extents in metres, found " +
                              std::to_string(size.size()) + " values");
    } else {
      object.size_m = {size[0], size[1], 0.0};
    }
    refuse("radius_m");
    refuse("length_m");
  } else {
    // The shape itself was already reported; still consume the size keys so they are not also
    // reported as unknown.
    map.number_or("radius_m", 0.0);
    map.number_or("length_m", 0.0);
    map.vector3_or("size_m", {0.0, 0.0, 0.0});
  }
  object.pose.xyz_m = map.vector3("xyz_m");
  object.pose.rpy_rad = map.angles3_rad_or("rpy", {0.0, 0.0, 0.0});
  object.rgb = read_rgb(map, "rgb", object.rgb);
  if (auto texture = map.optional_map("texture")) {
    object.texture = read_texture(std::move(*texture), object.texture);
    if (object.texture.kind == TextureKind::kChessboard) check_chessboard_object(map, object);
  }
  const std::string body = map.choice_or("body", {"static", "free", "scripted"}, "static");
  object.body = body == "free"       ? BodyKind::kFree
                : body == "scripted" ? BodyKind::kScripted
                                     : BodyKind::kStatic;
  object.mass_kg = map.number_or("mass_kg", object.mass_kg, Range::positive());
  object.friction = map.number_or("friction", object.friction, Range::positive());
  if (map.has("mass_kg") && object.body != BodyKind::kFree) {
    map.error("mass_kg", "only a free body has a mass (body is '" + body + "')");
  }
  if (auto motion = map.optional_map("motion")) {
    object.motion = read_motion(std::move(*motion));
    if (object.body != BodyKind::kScripted) {
      map.error("motion", "only a scripted body follows a motion (set body: scripted)");
    }
  } else if (object.body == BodyKind::kScripted) {
    map.error("body", "a scripted body needs a motion");
  }
  if (object.shape == ShapeKind::kPlane && object.body != BodyKind::kStatic) {
    map.error("body", "a plane can only be static");
  }
  map.finish();
  return object;
}

}  // namespace

const SceneObjectConfig* SceneConfig::find_object(const std::string& object_name) const {
  for (const auto& object : objects) {
    if (object.name == object_name) return &object;
  }
  return nullptr;
}

SceneConfig read_scene(MapReader root, const std::string& file) {
  SceneConfig scene;
  scene.source_file = file;
  if (auto header = root.optional_map("scene")) {
    scene.name = header->text("name");
    header->finish();
  } else {
    scene.name = std::filesystem::path(file).stem().string();
  }
  if (auto world = root.optional_map("world")) {
    scene.floor = world->boolean_or("floor", scene.floor);
    scene.floor_rgb = read_rgb(*world, "floor_rgb", scene.floor_rgb);
    if (auto texture = world->optional_map("floor_texture")) {
      scene.floor_texture = read_texture(std::move(*texture), scene.floor_texture);
      if (scene.floor_texture.kind == TextureKind::kChessboard) {
        world->error("floor_texture",
                     "a chessboard goes on a box (a calibration board), not the floor");
      }
    }
    scene.sky_rgb = read_rgb(*world, "sky_rgb", scene.sky_rgb);
    world->finish();
  }
  if (auto overview = root.optional_map("overview_camera")) {
    scene.overview.xyz_m = overview->vector3_or("xyz_m", scene.overview.xyz_m);
    scene.overview.look_at_m = overview->vector3_or("look_at_m", scene.overview.look_at_m);
    scene.overview.fovy_rad = overview->angle_rad_or("fovy", scene.overview.fovy_rad,
                                                     Range{0.0, std::numbers::pi, true, true});
    overview->finish();
  }
  std::set<std::string> names;
  if (root.has("objects")) {
    std::vector<MapReader> object_maps = root.map_list("objects");
    if (object_maps.size() > kMaxSceneObjects) {
      root.error("objects", "expected at most " + std::to_string(kMaxSceneObjects) +
                                " objects (each is a body the sim collides every physics step, "
                                "sized into MuJoCo's arena at load), found " +
                                std::to_string(object_maps.size()));
    }
    for (auto& object_map : object_maps) {
      SceneObjectConfig object = read_object(object_map);
      if (!object.name.empty() && !names.insert(object.name).second) {
        object_map.error("name", "duplicate object name '" + object.name + "'");
      }
      scene.objects.push_back(std::move(object));
    }
  }
  root.finish();
  root.issues()->throw_if_any();
  return scene;
}

SceneConfig load_scene(const std::string& path, const std::vector<ConfigOverride>& overrides) {
  auto document = ConfigDocument::load_file(path, overrides);
  return read_scene(document.root(), path);
}

SceneConfig load_scene_from_string(const std::string& yaml, const std::string& name,
                                   const std::vector<ConfigOverride>& overrides) {
  auto document = ConfigDocument::from_string(yaml, name, overrides);
  return read_scene(document.root(), name);
}

}  // namespace cambio::config
