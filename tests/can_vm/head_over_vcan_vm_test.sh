#!/usr/bin/env bash
# head_over_vcan_vm_test.sh CAMBIO: the main job's vergence experiment with the head's five
# drives on CAN: `cambio virtual-rig` emulates them on vcan0 in one process, `cambio run` drives
# them as the CANopen master in another, the two talking only through the kernel's CAN stack; the
# sim's head follows the positions the drives report, so the cameras see what the drives did. The
# eyes must verge as they do in the sim: the experiment's goals (|disparity| <= 0.5 px, true gaze
# error <= 0.1 deg) met, exit 0; settling gets 30 s instead of 1 at these rates, and no key frames
# are rendered (each would take seconds of the emulated CPU from the drives' master).
# Runs inside the QEMU guest (tests/can_vm/run_in_guest.sh), ~50x slower than the host: small
# images, lower camera, perception and joint rates and a longer run; judged on convergence only.
set -uo pipefail

cambio=${1:?usage: head_over_vcan_vm_test.sh CAMBIO}
repo=$(cd -- "$(dirname -- "${BASH_SOURCE[0]}")/../.." && pwd -P)
work=$(mktemp -d -p "${CAMBIO_BUILD_DIR:-/tmp}" head_over_vcan_vm_test.XXXXXX)

rig_sets=(--set groups.head.backend=socketcan --set can_buses.can0.interface=vcan0)
"${cambio}" virtual-rig --config "${repo}/firmware_config/rigs/cambio.yaml" "${rig_sets[@]}" \
  >"${work}/rig.log" 2>&1 &
rig_pid=$!
trap 'kill -INT "${rig_pid}" 2>/dev/null; wait' EXIT

camera_sets=()
for eye in left_eye right_eye; do
  camera_sets+=(--set "rig.cameras.${eye}.width_px=320" --set "rig.cameras.${eye}.height_px=240"
    --set "rig.cameras.${eye}.focal_px=277.128" --set "rig.cameras.${eye}.principal_point_px=[159.5,119.5]")
done
"${cambio}" run "${repo}/firmware_config/experiments/vergence_sphere.yaml" \
  --set rig.groups.head.backend=socketcan --set rig.can_buses.can0.interface=vcan0 \
  "${camera_sets[@]}" \
  --set rig.loops.joint.rate_hz=100 --set rig.loops.control.rate_hz=50 \
  --set rig.loops.perception.rate_hz=5 --set rig.loops.camera.rate_hz=5 \
  --set rig.sim.physics_rate_hz=200 --set experiment.duration_s=40 \
  --set experiment.goals.settle_time_s.max=30 --set 'experiment.evaluation.key_frames_s=[]' \
  --out "${work}/out" >"${work}/run.log" 2>&1
status=$?
kill -INT "${rig_pid}"
wait "${rig_pid}"
trap - EXIT

cat "${work}/run.log"
echo "--- virtual rig"
cat "${work}/rig.log"
if [[ ${status} -ne 0 ]]; then
  echo "head_over_vcan_vm_test: FAILED: cambio run exited ${status} (logs in ${work})"
  exit 1
fi
# (grep, not Python: Python takes 6 s to start under the guest's emulated CPU.)
echo "head_over_vcan_vm_test: the eyes verged with the head on CAN (vcan0); peak RSS of cambio run" \
  "$(grep -oE '"peak_rss_kib": *[0-9]+' "${work}/out/summary.json" | grep -oE '[0-9]+$') KiB"
rm -rf "${work}"
