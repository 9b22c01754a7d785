#!/usr/bin/env bash
# v4l2_vivid_vm_test.sh TEST_BINARY CAMBIO VIVID_INJECT: the v4l2 backend on the kernel's V4L2
# stack, in the QEMU guest of run_in_guest.sh (the host kernel has no V4L2). Loads vivid, the
# kernel's virtual video driver, as five instances: 0, 1, 3 and 4 each with one HDMI input and one
# HDMI output (looped, so a frame written to the output comes back on the capture node), 2 with a
# webcam input (discrete sizes and rates, for the refusals); then runs TEST_BINARY
# (tests/drivers/v4l2/v4l2_vivid_vm_test.cpp) on 0, 1 and 2, with the nodes found by name in sysfs.
# Then the real rig whole, in the same boot: VIVID_INJECT streams a stereo pair (a texture and the
# same moved 4 px) to instances 3 and 4; `cambio run` reads them with both eyes on `v4l2` and the
# head's five drives on vcan0 (emulated by `cambio virtual-rig` in another process), every backend
# a kernel interface, for 10 s. It must end with exit 0, every frame of both eyes paired, and the
# SSM's disparity at the fovea what `cambio perceive` gives for the same two files.
set -uo pipefail

usage="usage: v4l2_vivid_vm_test.sh TEST_BINARY CAMBIO VIVID_INJECT"
binary=${1:?${usage}}
cambio=${2:?${usage}}
inject=${3:?${usage}}
repo=$(cd -- "$(dirname -- "${BASH_SOURCE[0]}")/../.." && pwd -P)
say() { printf 'v4l2_vivid_vm_test: %s\n' "$*"; }

media=$(ls -d "${CAMBIO_BUILD_DIR:-/nonexistent}"/can_vm/linux-image-*/media 2>/dev/null | sort -V | tail -n 1)
if [[ ! -f ${media}/vivid.ko ]]; then
  say "no vivid.ko under ${CAMBIO_BUILD_DIR:-<unset CAMBIO_BUILD_DIR>}/can_vm/*/media"
  exit 1
fi
while read -r module; do
  [[ ${module} == vivid ]] && continue
  busybox insmod "${media}/${module}.ko" || { say "insmod ${module} failed"; exit 1; }
done <"${media}/modules.order"
# node_types 0x101: a video capture and a video output node; input_types 2 bits per input
# (3 = HDMI, 0 = webcam); output_types 1 bit per output (1 = HDMI).
busybox insmod "${media}/vivid.ko" n_devs=5 node_types=0x101,0x101,0x1,0x101,0x101 \
  num_inputs=1,1,1,1,1 input_types=0x3,0x3,0x0,0x3,0x3 num_outputs=1,1,1,1,1 \
  output_types=0x1,0x1,0x0,0x1,0x1 ||
  { say "insmod vivid failed"; exit 1; }

node() {  # node NAME: the /dev node whose sysfs name is NAME
  local dir
  for dir in /sys/class/video4linux/video*; do
    [[ $(cat "${dir}/name") == "$1" ]] && { printf '/dev/%s\n' "$(basename "${dir}")"; return 0; }
  done
  say "no V4L2 node named $1"
  return 1
}
CAMBIO_VIVID_LEFT_CAP=$(node vivid-000-vid-cap) && CAMBIO_VIVID_LEFT_OUT=$(node vivid-000-vid-out) &&
  CAMBIO_VIVID_RIGHT_CAP=$(node vivid-001-vid-cap) && CAMBIO_VIVID_RIGHT_OUT=$(node vivid-001-vid-out) &&
  CAMBIO_VIVID_WEBCAM=$(node vivid-002-vid-cap) || exit 1
export CAMBIO_VIVID_LEFT_CAP CAMBIO_VIVID_LEFT_OUT CAMBIO_VIVID_RIGHT_CAP CAMBIO_VIVID_RIGHT_OUT \
  CAMBIO_VIVID_WEBCAM
say "eyes: ${CAMBIO_VIVID_LEFT_OUT} -> ${CAMBIO_VIVID_LEFT_CAP}, ${CAMBIO_VIVID_RIGHT_OUT} -> ${CAMBIO_VIVID_RIGHT_CAP}; webcam ${CAMBIO_VIVID_WEBCAM}"
"${binary}" || exit 1

# The real rig whole: head on CAN, eyes on V4L2, reading an injected pair. The guest's CPU is
# emulated: 5 Hz camera and perception loops (the devices stream at 59.94 Hz; the newest frame
# wins), 100 Hz joints, as head_over_vcan_vm_test.sh.
work=$(mktemp -d -p "${CAMBIO_BUILD_DIR:-/tmp}" real_rig_vm.XXXXXX)
"${inject}" --write-pair "${work}" 4 || exit 1
left_eye=$(node vivid-003-vid-cap) && right_eye=$(node vivid-004-vid-cap) &&
  left_out=$(node vivid-003-vid-out) && right_out=$(node vivid-004-vid-out) || exit 1
"${inject}" "${left_out}" "${left_eye}" "${work}/left.pgm" &
left_pid=$!
"${inject}" "${right_out}" "${right_eye}" "${work}/right.pgm" &
right_pid=$!
"${cambio}" virtual-rig --config "${repo}/firmware_config/rigs/cambio.yaml" \
  --set groups.head.backend=socketcan --set can_buses.can0.interface=vcan0 >"${work}/rig.log" 2>&1 &
rig_pid=$!
trap 'kill -INT "${rig_pid}" "${left_pid}" "${right_pid}" 2>/dev/null; wait' EXIT
sleep 1
camera_sets=()
for eye in left_eye right_eye; do
  camera_sets+=(--set "rig.cameras.${eye}.backend=v4l2" --set "rig.cameras.${eye}.device=${!eye}"
    --set "rig.cameras.${eye}.pixel_format=YUYV" --set "rig.cameras.${eye}.frame_rate_hz=59.94"
    --set "rig.cameras.${eye}.format=grey8")
done
"${cambio}" run "${repo}/tests/apps/data/sim_hold.yaml" \
  --set rig.groups.head.backend=socketcan --set rig.can_buses.can0.interface=vcan0 \
  "${camera_sets[@]}" \
  --set rig.loops.joint.rate_hz=100 --set rig.loops.control.rate_hz=50 \
  --set rig.loops.perception.rate_hz=5 --set rig.loops.camera.rate_hz=5 \
  --set rig.sim.physics_rate_hz=200 --set experiment.duration_s=10 \
  --out "${work}/out" >"${work}/run.log" 2>&1
status=$?
cat "${work}/run.log"
if [[ ${status} -ne 0 ]]; then
  echo "--- virtual rig"; cat "${work}/rig.log"
  say "FAILED: the run with the head on CAN and the eyes on V4L2 exited ${status} (logs in ${work})"
  exit 1
fi
for eye in left_eye right_eye; do
  grep -qE "v4l2: camera '${eye}': [1-9][0-9]* frames delivered" "${work}/run.log" ||
    { say "FAILED: no frames from ${eye} (logs in ${work})"; exit 1; }
done
grep -qE "v4l2: stereo pair: [1-9][0-9]* pairs" "${work}/run.log" ||
  { say "FAILED: no stereo pairs (logs in ${work})"; exit 1; }
# The SSM's disparity in the run against `cambio perceive` on the two files injected, with the
# run's perception config (the run adds the whole-range scan the rig's geometry calls for; on a
# 4-px shift of a textured pair both end on the same finest-level peak).
"${cambio}" perceive --left "${work}/left.pgm" --right "${work}/right.pgm" \
  --config "${repo}/firmware_config/perception/vergence.yaml" --out "${work}/perceive" \
  >"${work}/perceive.log" 2>&1 || { cat "${work}/perceive.log"; say "FAILED: perceive"; exit 1; }
run_px=$(grep -oE 'final_disparity_px=[-0-9.e]+' "${work}/run.log" | head -n 1 | cut -d= -f2)
perceive_px=$(grep -oE '"disparity_px": *[-0-9.e]+' "${work}/perceive/result.json" | head -n 1 |
  grep -oE '[-0-9.e]+$')
say "SSM disparity at the fovea: ${run_px} px in the run, ${perceive_px} px from cambio perceive"
awk -v a="${run_px}" -v b="${perceive_px}" 'BEGIN { d = a - (b < 0 ? -b : b); exit !(d < 0.05 && d > -0.05) }' ||
  { say "FAILED: the run's disparity is not perceive's (logs in ${work})"; exit 1; }
kill -INT "${rig_pid}" "${left_pid}" "${right_pid}"
wait
trap - EXIT
say "the real rig whole: head on vcan0, eyes on ${left_eye} and ${right_eye} reading the injected pair, ran 10 s"
rm -rf "${work}"
