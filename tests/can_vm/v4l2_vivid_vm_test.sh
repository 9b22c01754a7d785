#!/usr/bin/env bash
# v4l2_vivid_vm_test.sh TEST_BINARY CAMBIO: the v4l2 backend on the kernel's V4L2 stack, in the
# QEMU guest of run_in_guest.sh (the host kernel has no V4L2). Loads vivid, the kernel's virtual
# video driver, as five instances: 0 and 1 each with one HDMI input and one HDMI output (looped,
# so a frame written to the output comes back on the capture node: the two eyes), 2 with a webcam
# input (discrete sizes and rates, for the refusals), 3 and 4 webcams for the whole rig; then runs
# TEST_BINARY (tests/drivers/v4l2/v4l2_vivid_vm_test.cpp) with the nodes found by name in sysfs.
# Then the real rig whole, in the same boot: `cambio run` with the head's drives on vcan0
# (emulated by `cambio virtual-rig` in another process) and the eyes on the two webcams, every
# backend a kernel interface; it must run to its end (exit 0) with frames from both eyes, paired.
set -uo pipefail

binary=${1:?usage: v4l2_vivid_vm_test.sh TEST_BINARY CAMBIO}
cambio=${2:?usage: v4l2_vivid_vm_test.sh TEST_BINARY CAMBIO}
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
busybox insmod "${media}/vivid.ko" n_devs=5 node_types=0x101,0x101,0x1,0x1,0x1 \
  num_inputs=1,1,1,1,1 input_types=0x3,0x3,0x0,0x0,0x0 num_outputs=1,1,1,1,1 \
  output_types=0x1,0x1,0x0,0x0,0x0 ||
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

# The real rig whole: head on CAN, eyes on V4L2. The guest's CPU is emulated (~50x slower than
# the host): 5 Hz cameras and perception, 100 Hz joints, as head_over_vcan_vm_test.sh.
left_eye=$(node vivid-003-vid-cap) && right_eye=$(node vivid-004-vid-cap) || exit 1
work=$(mktemp -d -p "${CAMBIO_BUILD_DIR:-/tmp}" real_rig_vm.XXXXXX)
"${cambio}" virtual-rig --config "${repo}/firmware_config/rigs/cambio.yaml" \
  --set groups.head.backend=socketcan --set can_buses.can0.interface=vcan0 >"${work}/rig.log" 2>&1 &
rig_pid=$!
camera_sets=()
for eye in left_eye right_eye; do
  camera_sets+=(--set "rig.cameras.${eye}.backend=v4l2" --set "rig.cameras.${eye}.device=${!eye}"
    --set "rig.cameras.${eye}.pixel_format=YUYV" --set "rig.cameras.${eye}.frame_rate_hz=5")
done
"${cambio}" run "${repo}/tests/apps/data/sim_hold.yaml" \
  --set rig.groups.head.backend=socketcan --set rig.can_buses.can0.interface=vcan0 \
  "${camera_sets[@]}" \
  --set rig.loops.joint.rate_hz=100 --set rig.loops.control.rate_hz=50 \
  --set rig.loops.perception.rate_hz=5 --set rig.loops.camera.rate_hz=5 \
  --set rig.sim.physics_rate_hz=200 --set experiment.duration_s=8 \
  --out "${work}/out" >"${work}/run.log" 2>&1
status=$?
kill -INT "${rig_pid}"
wait "${rig_pid}"
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
say "the real rig whole: head on vcan0, eyes on ${left_eye} and ${right_eye}, ran to its end"
rm -rf "${work}"
