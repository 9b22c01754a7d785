#!/usr/bin/env bash
# v4l2_vivid_vm_test.sh TEST_BINARY: the v4l2 backend on the kernel's V4L2 stack, in the QEMU
# guest of run_in_guest.sh (the host kernel has no V4L2). Loads vivid, the kernel's virtual video
# driver, as three instances: 0 and 1 each with one HDMI input and one HDMI output (looped, so a
# frame written to the output comes back on the capture node: the two eyes), 2 with a webcam
# input (discrete sizes and rates, for the refusals); then runs TEST_BINARY
# (tests/drivers/v4l2/v4l2_vivid_vm_test.cpp) with the nodes found by name in sysfs.
set -uo pipefail

binary=${1:?usage: v4l2_vivid_vm_test.sh TEST_BINARY}
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
busybox insmod "${media}/vivid.ko" n_devs=3 node_types=0x101,0x101,0x1 num_inputs=1,1,1 \
  input_types=0x3,0x3,0x0 num_outputs=1,1,1 output_types=0x1,0x1,0x0 ||
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
"${binary}"
