#include "view_culling.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <mujoco/mujoco.h>
#include <Eigen/Geometry>

namespace cambio::sim {

namespace {

using Vec3 = Eigen::Vector3d;

Vec3 from(const float* v) {
  return {v[0], v[1], v[2]};
}

// A half-space n . p + d >= 0 that contains the frustum.
struct HalfSpace {
  Vec3 normal;
  double offset;
  double signed_distance(const Vec3& p) const { return normal.dot(p) + offset; }
};

// The six half-spaces of MuJoCo's OpenGL frustum (mjr_render: left/right from the centre and the
// viewport's aspect, bottom/top/near/far as given), in the world frame.
std::array<HalfSpace, 6> frustum_of(const mjvGLCamera& camera, double aspect) {
  const Vec3 position = from(camera.pos);
  const Vec3 forward = from(camera.forward).normalized();
  const Vec3 up = from(camera.up).normalized();
  const Vec3 right = forward.cross(up);
  const double near = camera.frustum_near;
  const double half_width = 0.5 * aspect * (camera.frustum_top - camera.frustum_bottom);
  const double left = camera.frustum_center - half_width;
  const double right_edge = camera.frustum_center + half_width;
  // A side plane through the eye containing the edge direction near*forward + edge*axis; its
  // inward normal is perpendicular to that edge and to the other image axis.
  const Vec3 centre = near * forward;
  const Vec3 inside = centre + static_cast<double>(camera.frustum_center) * right +
                      0.5 * (camera.frustum_bottom + camera.frustum_top) * up;
  auto side = [&](const Vec3& edge_direction, const Vec3& other_axis) {
    Vec3 normal = edge_direction.cross(other_axis).normalized();
    if (normal.dot(inside) < 0.0) normal = -1.0 * normal;
    return HalfSpace{normal, -normal.dot(position)};
  };
  return {
      HalfSpace{forward, -forward.dot(position + near * forward)},
      HalfSpace{-1.0 * forward,
                forward.dot(position + static_cast<double>(camera.frustum_far) * forward)},
      side(centre + left * right, up),
      side(centre + right_edge * right, up),
      side(centre + camera.frustum_bottom * up, right),
      side(centre + camera.frustum_top * up, right),
  };
}

bool outside(const mjvGeom& geom, const std::array<HalfSpace, 6>& frustum) {
  const Vec3 centre = from(geom.pos);
  if (geom.type == mjGEOM_PLANE) {
    // A finite rectangle: outside when its four corners are behind one plane of the frustum.
    const Vec3 axis_x{geom.mat[0], geom.mat[3], geom.mat[6]};
    const Vec3 axis_y{geom.mat[1], geom.mat[4], geom.mat[7]};
    const Vec3 half_x = static_cast<double>(geom.size[0]) * axis_x;
    const Vec3 half_y = static_cast<double>(geom.size[1]) * axis_y;
    const std::array<Vec3, 4> corners = {centre + half_x + half_y, centre + half_x - half_y,
                                         centre - half_x + half_y, centre - half_x - half_y};
    return std::any_of(frustum.begin(), frustum.end(), [&](const HalfSpace& plane) {
      return std::all_of(corners.begin(), corners.end(),
                         [&](const Vec3& corner) { return plane.signed_distance(corner) < 0.0; });
    });
  }
  const double radius = geom.modelrbound;
  if (!(radius > 0.0)) return false;  // Extent unknown: drawn.
  return std::any_of(frustum.begin(), frustum.end(), [&](const HalfSpace& plane) {
    return plane.signed_distance(centre) < -radius;
  });
}

}  // namespace

void cull_and_order_for_view(mjvScene_* scene, double aspect) {
  const auto frustum = frustum_of(scene->camera[0], aspect);
  int kept = 0;
  for (int i = 0; i < scene->ngeom; ++i) {
    if (outside(scene->geoms[i], frustum)) continue;
    if (kept != i) scene->geoms[kept] = scene->geoms[i];
    ++kept;
  }
  scene->ngeom = kept;
  // Nearest first (MuJoCo sorts the transparent ones again itself, farthest first). The distance
  // is to the geom's centre, a fair order for compact objects; a plane's centre may be far from
  // its nearest point, so planes go last: they are the floor and the sky, behind most of what
  // the eyes look at. An insertion sort: a few dozen geoms, no allocation, stable.
  const Vec3 eye = from(scene->camera[0].pos);
  for (int i = 0; i < kept; ++i) {
    mjvGeom& geom = scene->geoms[i];
    const Vec3 offset = from(geom.pos) - eye;
    geom.camdist = geom.type == mjGEOM_PLANE ? 1e30F : static_cast<float>(offset.norm());
  }
  for (int i = 1; i < kept; ++i) {
    if (!(scene->geoms[i].camdist < scene->geoms[i - 1].camdist)) continue;
    const mjvGeom moving = scene->geoms[i];
    int j = i;
    for (; j > 0 && moving.camdist < scene->geoms[j - 1].camdist; --j) {
      scene->geoms[j] = scene->geoms[j - 1];
    }
    scene->geoms[j] = moving;
  }
}

}  // namespace cambio::sim
