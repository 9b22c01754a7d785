#include "cambio/sim/world_snapshot.hpp"

#include <algorithm>

#include <mujoco/mujoco.h>

namespace cambio::sim {

void WorldSnapshot::resize_for(const mjModel* model) {
  qpos.assign(static_cast<std::size_t>(model->nq), 0.0);
  qvel.assign(static_cast<std::size_t>(model->nv), 0.0);
  mocap_pos.assign(static_cast<std::size_t>(model->nmocap) * 3, 0.0);
  mocap_quat.assign(static_cast<std::size_t>(model->nmocap) * 4, 0.0);
}

void WorldSnapshot::capture(const mjModel* model, const mjData* data, std::int64_t stamp,
                            std::uint64_t steps) noexcept {
  stamp_ns = stamp;
  step = steps;
  time_s = data->time;
  std::copy_n(data->qpos, model->nq, qpos.data());
  std::copy_n(data->qvel, model->nv, qvel.data());
  std::copy_n(data->mocap_pos, model->nmocap * 3, mocap_pos.data());
  std::copy_n(data->mocap_quat, model->nmocap * 4, mocap_quat.data());
}

void WorldSnapshot::restore(const mjModel* model, mjData* data) const noexcept {
  data->time = time_s;
  std::copy_n(qpos.data(), model->nq, data->qpos);
  std::copy_n(qvel.data(), model->nv, data->qvel);
  std::copy_n(mocap_pos.data(), model->nmocap * 3, data->mocap_pos);
  std::copy_n(mocap_quat.data(), model->nmocap * 4, data->mocap_quat);
}

}  // namespace cambio::sim
