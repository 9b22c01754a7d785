#pragma once

struct mjvScene_;

namespace cambio::sim {

/// Drops from `scene` the geoms wholly outside the view frustum of its camera (scene->camera[0],
/// as mjv_updateScene set it, for a viewport of aspect `width / height`) and orders the opaque
/// ones nearest first, so the rasteriser's depth test rejects hidden fragments before they are
/// shaded and textured. MuJoCo 2.2 draws every geom of the scene in the order it was added (the
/// world's planes first); on a software rasteriser both the vertices of geoms out of view and the
/// fragments of the sky behind the scene are paid for in full.
///
/// Only for views without shadows or reflections (those draw geoms outside the frustum).
/// Geoms of unknown extent (decor, rbound 0, not a plane) are kept. Allocation-free.
void cull_and_order_for_view(mjvScene_* scene, double aspect);

}  // namespace cambio::sim
