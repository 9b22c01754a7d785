#!/usr/bin/env bash
# run_in_guest.sh COMMAND [ARG...]
#
# Runs COMMAND inside a throwaway QEMU guest that has a kernel CAN stack (this host's kernel may
# not: socket(PF_CAN) fails with EAFNOSUPPORT), with vcan0 (CAN FD, mtu 72) and vcan1 (classic,
# mtu 16) up, and exits with COMMAND's exit status. The README's "Run on CAN" shows its use; the
# comments below say why each choice was made (software emulation, the CPU model, the 9p root).
#
# The guest boots Debian's stock kernel (downloaded with apt-get download, never installed) with a
# busybox initramfs, sees the host's root read-only over 9p, and runs COMMAND chrooted into it, in
# the current directory, as root. Shared read-write at the same paths: the current directory, this
# source tree, the build directory (${CAMBIO_BUILD_DIR:-<repo>/build}) and every path listed in CAN_VM_SHARE
# (colon-separated). /tmp, /run, /var/tmp and /dev/shm are fresh tmpfs in the guest.
#
# Environment passed into the guest: PATH, HOME, LANG, LC_*, TERM, TZ, GTEST_*, CAMBIO_*,
# ASAN_/UBSAN_/LSAN_OPTIONS, and every variable named in CAN_VM_ENV (space-separated);
# GALLIUM_DRIVER is softpipe unless set (Mesa's llvmpipe takes seconds to start under emulation).
# Knobs: CAN_VM_TIMEOUT_S (default 900), CAN_VM_MEMORY_MB (512), CAN_VM_CPUS (2),
# CAN_VM_NO_INSTALL=1 (never call apt), CAN_VM_QEMU (the qemu binary).
#
# Exit status: COMMAND's own; 77 when the guest cannot start here (says why; ctest's SKIP code);
# 125 when the guest started but gave no status back (boot failure, crash, timeout).
# Cache (kernel, modules, initramfs): ${CAMBIO_BUILD_DIR:-<repo>/build}/can_vm/; the V4L2 modules
# (vivid and its dependencies, not loaded at boot) in <kernel>/media/ with their insmod order.
set -uo pipefail

readonly kSkip=77
readonly kNoStatus=125
readonly kPackages=(qemu-system-x86 busybox-static can-utils iproute2 xz-utils)
# insmod order (dependencies first); a module missing from the package is built in and skipped.
readonly kModules=(virtio_ring virtio virtio_pci_legacy_dev virtio_pci_modern_dev virtio_pci
  9pnet 9pnet_virtio netfs fscache 9p can can-raw can-bcm can-gw can-dev vcan vxcan)
# V4L2's test driver and its dependencies in insmod order, unpacked into <kernel>/media/ but not
# loaded at boot: a V4L2 test loads vivid with the parameters it needs (v4l2_vivid_vm_test.sh).
readonly kMediaModules=(mc rc-core cec videodev v4l2-dv-timings v4l2-tpg videobuf2-common
  videobuf2-memops videobuf2-v4l2 videobuf2-vmalloc videobuf2-dma-contig vivid)

script_dir=$(cd -- "$(dirname -- "${BASH_SOURCE[0]}")" && pwd -P)
repo_dir=$(cd -- "${script_dir}/../.." && pwd -P)
build_dir=${CAMBIO_BUILD_DIR:-${repo_dir}/build}
cache_dir=${build_dir}/can_vm
qemu=${CAN_VM_QEMU:-qemu-system-x86_64}
timeout_s=${CAN_VM_TIMEOUT_S:-900}
memory_mb=${CAN_VM_MEMORY_MB:-512}
cpus=${CAN_VM_CPUS:-2}

say() { printf 'run_in_guest: %s\n' "$*" >&2; }
skip() {
  say "SKIPPED: $* (the guest cannot start on this machine)"
  exit "${kSkip}"
}

if [[ $# -eq 0 ]]; then
  say "usage: run_in_guest.sh COMMAND [ARG...]"
  exit 2
fi
for number in "${timeout_s}" "${memory_mb}" "${cpus}"; do
  [[ ${number} =~ ^[1-9][0-9]*$ ]] || {
    say "CAN_VM_TIMEOUT_S, CAN_VM_MEMORY_MB and CAN_VM_CPUS must be positive integers, found '${number}'"
    exit 2
  }
done
if [[ $(uname -m) != x86_64 ]]; then
  skip "the harness emulates an x86_64 guest running this host's binaries; this host is $(uname -m)"
fi

mkdir -p -- "${cache_dir}" || skip "cannot create the cache directory ${cache_dir}"
build_dir=$(cd -- "${build_dir}" && pwd -P)
cache_dir=${build_dir}/can_vm

as_root() {
  if [[ $(id -u) -eq 0 ]]; then
    "$@"
  elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
    sudo -n "$@"
  else
    return 1
  fi
}

apt_get() { as_root env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=300 "$@"; }

# Installs the host packages the guest needs, once; a missing one we cannot install means SKIP.
ensure_packages() {
  local missing=() package
  for package in "${kPackages[@]}"; do
    dpkg-query -W -f='${Status}' "${package}" 2>/dev/null | grep -q 'install ok installed' ||
      missing+=("${package}")
  done
  [[ ${#missing[@]} -eq 0 ]] && return 0
  command -v apt-get >/dev/null || skip "missing packages ${missing[*]} and no apt-get to install them"
  [[ ${CAN_VM_NO_INSTALL:-0} == 1 ]] && skip "missing packages ${missing[*]} (CAN_VM_NO_INSTALL=1)"
  say "installing ${missing[*]}"
  if ! apt_get install -y -q --no-install-recommends "${missing[@]}" >&2; then
    apt_get update -q >&2 && apt_get install -y -q --no-install-recommends "${missing[@]}" >&2 ||
      skip "missing packages ${missing[*]} and cannot install them (need root or sudo, and apt)"
  fi
}

# Prints the versioned kernel package (linux-image-6.1.0-NN-amd64) linux-image-amd64 points to now.
current_kernel_package() {
  apt-cache depends linux-image-amd64 2>/dev/null |
    sed -n 's/^ *Depends: \(linux-image-[0-9][^ ]*-amd64\)$/\1/p' | head -n 1
}

# Downloads and unpacks the kernel package into ${cache_dir}/<package>/ (vmlinux or vmlinuz, and
# the modules in insmod order), and prints that directory.
ensure_kernel() {
  local package
  package=$(current_kernel_package)
  if [[ -z ${package} && ${CAN_VM_NO_INSTALL:-0} != 1 ]] && [[ -z $(ls -d "${cache_dir}"/linux-image-*/ 2>/dev/null) ]]; then
    apt_get update -q >&2 && package=$(current_kernel_package)
  fi
  if [[ -z ${package} ]]; then
    # Offline: the newest kernel already unpacked will do.
    package=$(ls -d "${cache_dir}"/linux-image-*/ 2>/dev/null | sort -V | tail -n 1)
    package=$(basename -- "${package:-/}")
    [[ -n ${package} ]] || skip "apt cannot resolve linux-image-amd64 and no kernel is cached in ${cache_dir}"
  fi
  local kernel_dir=${cache_dir}/${package}
  if [[ -f ${kernel_dir}/complete && -f ${kernel_dir}/media/modules.order ]]; then
    printf '%s\n' "${kernel_dir}"
    return 0
  fi
  [[ ${CAN_VM_NO_INSTALL:-0} == 1 ]] && skip "kernel ${package} not cached in ${cache_dir} (CAN_VM_NO_INSTALL=1)"
  say "downloading ${package} (once; cached in ${cache_dir})"
  local work
  work=$(mktemp -d "${cache_dir}/download.XXXXXX") || skip "cannot write to ${cache_dir}"
  (cd -- "${work}" && apt-get -q -o APT::Sandbox::User=root download "${package}" >&2) ||
    { rm -rf -- "${work}"; skip "apt-get download ${package} failed"; }
  mkdir -p -- "${work}/root" "${work}/out/modules"
  dpkg-deb --fsys-tarfile "${work}"/"${package}"_*.deb | tar -x -C "${work}/root" \
    --wildcards './boot/vmlinuz-*' '*/kernel/drivers/virtio/*' '*/kernel/net/9p/*' \
    '*/kernel/fs/9p/*' '*/kernel/fs/netfs/*' '*/kernel/fs/fscache/*' '*/kernel/net/can/*' \
    '*/kernel/drivers/net/can/*' '*/kernel/drivers/media/*' ||
    { rm -rf -- "${work}"; skip "cannot unpack ${package}"; }
  local module found order=()
  for module in "${kModules[@]}"; do
    found=$(find "${work}/root" -name "${module}.ko" -print -quit)
    if [[ -n ${found} ]]; then
      cp -- "${found}" "${work}/out/modules/" && order+=("${module}")
    fi
  done
  for module in can can-raw vcan; do
    [[ -f ${work}/out/modules/${module}.ko ]] || { rm -rf -- "${work}"; skip "${package} has no ${module}.ko"; }
  done
  printf '%s\n' "${order[@]}" >"${work}/out/modules.order"
  mkdir -p -- "${work}/out/media"
  order=()
  for module in "${kMediaModules[@]}"; do
    found=$(find "${work}/root" -name "${module}.ko" -print -quit)
    if [[ -n ${found} ]]; then
      cp -- "${found}" "${work}/out/media/" && order+=("${module}")
    fi
  done
  printf '%s\n' "${order[@]}" >"${work}/out/media/modules.order"
  local vmlinuz
  vmlinuz=$(ls "${work}"/root/boot/vmlinuz-* | head -n 1)
  # The bzImage's payload is an ELF vmlinux compressed with xz; booting it directly (PVH entry)
  # saves ~2 s of decompression under TCG. Fall back to the bzImage when it cannot be found.
  local offset
  offset=$(LC_ALL=C grep -obUaP '\xfd7zXZ\x00' "${vmlinuz}" 2>/dev/null | head -n 1 | cut -d: -f1)
  if [[ -n ${offset} ]]; then
    tail -c +$((offset + 1)) "${vmlinuz}" | xz -dcq >"${work}/out/vmlinux" 2>/dev/null
  fi
  if ! head -c 4 "${work}/out/vmlinux" 2>/dev/null | grep -q 'ELF'; then
    rm -f -- "${work}/out/vmlinux"
    cp -- "${vmlinuz}" "${work}/out/vmlinuz"
  fi
  rm -rf -- "${kernel_dir}"
  mv -- "${work}/out" "${kernel_dir}" && touch -- "${kernel_dir}/complete"
  rm -rf -- "${work}"
  printf '%s\n' "${kernel_dir}"
}

# The guest's /init: loads the modules, mounts the shares, brings up vcan0/vcan1, chroots into the
# host's root, runs /run/can_vm/command.sh, writes its status to /run/can_vm/status, powers off.
guest_init() {
  cat <<'EOF'
#!/bin/busybox sh
/bin/busybox mkdir -p /proc /sys /dev /newroot /ctl /sbin /usr/bin /usr/sbin
/bin/busybox --install -s
mount -t devtmpfs devtmpfs /dev
# The command's stdout goes to ttyS0 (the host's stdout), stderr to ttyS1 (the host's stderr);
# -opost keeps the bytes as written (no \n -> \r\n).
stty -F /dev/ttyS0 -opost -echo 2>/dev/null
stty -F /dev/ttyS1 -opost -echo 2>/dev/null
exec </dev/null >/dev/ttyS0 2>/dev/ttyS1
fail() {
  echo "can_vm guest: $*" >&2
  sync
  poweroff -f
}
mount -t proc proc /proc
mount -t sysfs sysfs /sys
while read -r module; do
  insmod "/lib/modules/${module}.ko" || fail "insmod ${module} failed"
done </lib/modules.order
p9='trans=virtio,version=9p2000.L,msize=512000'
mount -t 9p -o "${p9},ro,cache=loose" hostroot /newroot || fail "cannot mount the host root"
mount -t 9p -o "${p9}" ctl /ctl || fail "cannot mount the control share"
mount -t proc proc /newroot/proc
mount -t sysfs sysfs /newroot/sys
mount -t devtmpfs devtmpfs /newroot/dev
mkdir -p /newroot/dev/pts /newroot/dev/shm
mount -t devpts devpts /newroot/dev/pts
for dir in /tmp /run /var/tmp /dev/shm; do
  mount -t tmpfs -o mode=1777 tmpfs "/newroot${dir}" || fail "cannot mount a tmpfs on ${dir}"
done
mkdir -p /newroot/run/can_vm
mount --bind /ctl /newroot/run/can_vm
i=0
while read -r path; do
  [ -d "/newroot${path}" ] || mkdir -p "/newroot${path}"
  mount -t 9p -o "${p9}" "share${i}" "/newroot${path}" || fail "cannot mount ${path}"
  i=$((i + 1))
done </ctl/shares
ip=/usr/sbin/ip
[ -x "/newroot${ip}" ] || ip=/sbin/ip
chroot /newroot "${ip}" link set lo up
chroot /newroot "${ip}" link add dev vcan0 type vcan &&
  chroot /newroot "${ip}" link set vcan0 mtu 72 up &&
  chroot /newroot "${ip}" link add dev vcan1 type vcan &&
  chroot /newroot "${ip}" link set vcan1 mtu 16 up || fail "cannot bring up vcan0/vcan1"
chroot /newroot /bin/bash /run/can_vm/command.sh
echo $? >/ctl/status.tmp && mv /ctl/status.tmp /ctl/status
echo 0 >/proc/sys/kernel/printk
sync
poweroff -f
EOF
}

# Builds (once per kernel and init script) the initramfs: static busybox, /init, the modules.
ensure_initramfs() {
  local kernel_dir=$1 busybox
  busybox=$(command -v busybox) || busybox=/bin/busybox
  [[ -x ${busybox} ]] || skip "no busybox (package busybox-static)"
  LC_ALL=C readelf -l "${busybox}" 2>/dev/null | grep -q 'INTERP' &&
    skip "${busybox} is dynamically linked; the initramfs needs busybox-static"
  local key
  key=$({ guest_init; cat "${kernel_dir}/modules.order"; sha256sum "${busybox}"; } | sha256sum | cut -c1-16)
  local image=${kernel_dir}/initramfs-${key}.cpio
  [[ -s ${image} ]] && { printf '%s\n' "${image}"; return 0; }
  local work
  work=$(mktemp -d "${cache_dir}/initramfs.XXXXXX") || skip "cannot write to ${cache_dir}"
  mkdir -p -- "${work}/bin" "${work}/lib/modules"
  cp -- "${busybox}" "${work}/bin/busybox"
  cp -- "${kernel_dir}"/modules/*.ko "${work}/lib/modules/"
  cp -- "${kernel_dir}/modules.order" "${work}/lib/modules.order"
  guest_init >"${work}/init"
  chmod 755 -- "${work}/init" "${work}/bin/busybox"
  # No cpio on a stock host: busybox has one.
  (cd -- "${work}" && find . -mindepth 1 | "${busybox}" cpio -o -H newc >"${image}.tmp" 2>/dev/null) ||
    { rm -rf -- "${work}" "${image}.tmp"; skip "cannot build the initramfs"; }
  mv -- "${image}.tmp" "${image}"
  rm -rf -- "${work}"
  printf '%s\n' "${image}"
}

# Whether this qemu runs TCG on several host threads (MTTCG); probed once per qemu binary.
multithread_tcg_works() {
  local probe=${cache_dir}/mttcg-$(sha256sum <"$(command -v "${qemu}")" | cut -c1-16)
  if [[ ! -f ${probe} ]]; then
    if echo quit | timeout 20 "${qemu}" -accel tcg,thread=multi -smp 2 -nodefaults \
      -display none -monitor stdio >/dev/null 2>&1; then
      echo yes >"${probe}"
    else
      echo no >"${probe}"
    fi
  fi
  [[ $(cat "${probe}") == yes ]]
}

# --- set up (under a lock: parallel ctest entries share the cache) ---
exec {lock_fd}>"${cache_dir}/.lock" || skip "cannot lock ${cache_dir}/.lock"
flock "${lock_fd}"
ensure_packages
command -v "${qemu}" >/dev/null || skip "no ${qemu}"
kernel_dir=$(ensure_kernel) || exit $?
initramfs=$(ensure_initramfs "${kernel_dir}") || exit $?
accel=tcg
if [[ ${cpus} -gt 1 ]] && multithread_tcg_works; then accel=tcg,thread=multi; else cpus=1; fi
flock -u "${lock_fd}"
exec {lock_fd}>&-

kernel=${kernel_dir}/vmlinux
[[ -f ${kernel} ]] || kernel=${kernel_dir}/vmlinuz

# --- the run ---
ctl=$(mktemp -d "${cache_dir}/run.XXXXXX") || skip "cannot write to ${cache_dir}"
stderr_pump=
cleanup() {
  if [[ -n ${stderr_pump} ]]; then
    # Opening the fifo read-write never blocks and releases a reader still waiting for a writer.
    exec {unblock_fd}<>"${ctl}/stderr.out"
    exec {unblock_fd}>&-
    wait "${stderr_pump}" 2>/dev/null
  fi
  rm -rf -- "${ctl}"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# Shared read-write at the same paths: the current directory, the source tree (its scripts and
# firmware_config: the host's root is shared too, but a tree under /tmp would be hidden by the
# guest's own /tmp), the build directory, CAN_VM_SHARE.
# Sorted so a parent is mounted before a child; a path inside another share is already there.
cwd=$(pwd -P)
shares=()
IFS=: read -r -a extra_shares <<<"${CAN_VM_SHARE:-}"
while IFS= read -r path; do
  [[ -z ${path} ]] && continue
  covered=0
  for share in "${shares[@]}"; do
    [[ ${path} == "${share}" || ${path} == "${share}"/* ]] && covered=1
  done
  [[ ${covered} == 0 ]] && shares+=("${path}")
done < <(for path in "${cwd}" "${repo_dir}" "${build_dir}" "${extra_shares[@]}"; do
  [[ -n ${path} ]] && (cd -- "${path}" 2>/dev/null && pwd -P)
done | awk '{ print length($0) "\t" $0 }' | sort -n -k1,1 | cut -f2-)
virtfs=()
for i in "${!shares[@]}"; do
  [[ ${shares[i]} == *,* ]] && { say "cannot share a path with a comma: ${shares[i]}"; exit 2; }
  printf '%s\n' "${shares[i]}" >>"${ctl}/shares"
  virtfs+=(-virtfs "local,path=${shares[i]},mount_tag=share${i},security_model=none,multidevs=remap")
done
touch -- "${ctl}/shares"

# The command script: the environment passed through, cd, run.
{
  echo 'set +e'
  # Mesa renders with softpipe in the guest unless told otherwise: llvmpipe compiles its shaders
  # with LLVM at a process's first frame, 8-10 s under emulation for every `cambio run` (a 0.1 s
  # pan-tilt run started in 15 s with llvmpipe, 4.6 s with softpipe), and the guest's tests are
  # on CAN and V4L2, not on rendering, which the host's tests check with llvmpipe.
  printf 'export GALLIUM_DRIVER=%q\n' "${GALLIUM_DRIVER:-softpipe}"
  while IFS= read -r name; do
    printf 'export %s=%q\n' "${name}" "${!name}"
  done < <(compgen -e | grep -E '^(PATH|HOME|LANG|LC_[A-Z]+|TERM|TZ|GTEST_[A-Z_]+|CAMBIO_[A-Z0-9_]+|[AUL]SAN_OPTIONS)$')
  for name in ${CAN_VM_ENV:-}; do
    [[ -v ${name} ]] && printf 'export %s=%q\n' "${name}" "${!name}"
  done
  printf 'cd -- %q || exit 125\n' "${cwd}"
  printf '%q ' "$@"
  echo
} >"${ctl}/command.sh"

# qemu's pipe chardev writes to <path>.out and reads <path>.in (both fifos; nothing writes .in).
mkfifo -- "${ctl}/stderr.out" "${ctl}/stderr.in"
cat -- "${ctl}/stderr.out" >&2 &
stderr_pump=$!

# Why these settings: /dev/kvm on such hosts is paravirtual (no vmx) and a stock kernel does not
# boot under it, so the guest is emulated (TCG). -cpu max crashes Mesa's llvmpipe in the guest
# (QEMU 7.2's emulation of the AVX2 gather it JIT-compiles faults); without AVX2 the rendered
# images stay identical to the host's. The host root is shared read-only over 9p so the guest
# runs this machine's own binaries and libraries; nothing is installed into an image.
started_ns=$(date +%s%N)
timeout --kill-after=10 "${timeout_s}" "${qemu}" \
  -accel "${accel}" -cpu max,-avx2 -smp "${cpus}" -m "${memory_mb}" \
  -nodefaults -no-user-config -display none -no-reboot \
  -kernel "${kernel}" -initrd "${initramfs}" \
  -append "console=ttyS0 quiet loglevel=1 panic=-1 rdinit=/init" \
  -chardev stdio,id=out -serial chardev:out \
  -chardev "pipe,id=err,path=${ctl}/stderr" -serial chardev:err \
  -virtfs "local,path=/,mount_tag=hostroot,security_model=none,readonly=on,multidevs=remap" \
  -virtfs "local,path=${ctl},mount_tag=ctl,security_model=none" \
  "${virtfs[@]}" </dev/null
qemu_status=$?
elapsed_ms=$((($(date +%s%N) - started_ns) / 1000000))
[[ -n ${CAN_VM_VERBOSE:-} ]] && say "guest ran ${elapsed_ms} ms (${accel}, ${cpus} vCPU)"

if [[ -f ${ctl}/status ]]; then
  status=$(cat -- "${ctl}/status")
  [[ ${status} =~ ^[0-9]+$ ]] && exit "${status}"
fi
if [[ ${qemu_status} -eq 124 || ${qemu_status} -eq 137 ]]; then
  say "the guest timed out after ${timeout_s} s (CAN_VM_TIMEOUT_S) and gave no exit status"
else
  say "the guest gave no exit status (qemu exited ${qemu_status} after ${elapsed_ms} ms); see the console output above"
fi
exit "${kNoStatus}"
