#!/usr/bin/env bash
# Tests run_in_guest.sh itself with one guest boot: the command's exit status comes back, vcan0
# (CAN FD, mtu 72) and vcan1 (classic, mtu 16) are up, the current directory is shared
# read-write, the environment is passed through. Also, without booting, that a machine where the
# guest cannot start gets the SKIP status (77) and a reason.
set -u
harness=$(cd -- "$(dirname -- "${BASH_SOURCE[0]}")" && pwd -P)/run_in_guest.sh
fail() {
  echo "harness_test: FAILED: $*" >&2
  exit 1
}

skip_output=$(CAN_VM_QEMU=/nonexistent/qemu-system-x86_64 CAN_VM_NO_INSTALL=1 "${harness}" true 2>&1)
skip_status=$?
[[ ${skip_status} -eq 77 ]] || fail "a missing qemu gave status ${skip_status}, expected 77"
[[ ${skip_output} == *SKIPPED*qemu* ]] || fail "a missing qemu did not say why: ${skip_output}"

work=$(mktemp -d "${CAMBIO_BUILD_DIR:-/tmp}/can_vm_harness.XXXXXX") || fail "cannot create a work dir"
trap 'rm -rf -- "${work}"' EXIT
cd -- "${work}" || fail "cannot enter ${work}"
CAMBIO_CAN_VM_PROBE='passed through' "${harness}" sh -c '
  ip link show vcan0 | grep -q "mtu 72" || exit 1
  ip link show vcan1 | grep -q "mtu 16" || exit 1
  printf "%s\n" "${CAMBIO_CAN_VM_PROBE}" >written_in_guest
  ip link show vcan0 && exit 7'
status=$?
[[ ${status} -eq 77 ]] && exit 77
[[ ${status} -eq 7 ]] || fail "the guest command exited 7, the harness returned ${status}"
[[ $(cat written_in_guest 2>/dev/null) == 'passed through' ]] ||
  fail "the guest did not write the passed-through variable into the shared directory"
echo "harness_test: ok"
