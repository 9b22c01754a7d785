#!/usr/bin/env bash
# can_stack_vm_test.sh CAMBIO: the CANopen master (`cambio run`, pan-tilt rig on socketcan) against
# the emulated drives (`cambio virtual-rig`) in two processes talking only through the kernel's
# CAN stack on vcan0, with can-utils as the independent peer (candump -L records, cansend injects,
# canplayer replays).
#
# The traffic is made inside the QEMU guest (tests/can_vm/run_in_guest.sh runs this script again
# with --in-guest) and judged here on the host from what the guest left in the work folder: under
# the guest's emulated CPU everything is ~50x slower than on the host and Python takes 6 s to
# start, against 0.2 s for grep or awk. The checks are on correctness and order, never on timing,
# except the issue's bound on fault latching (3 heartbeat periods), read from candump's kernel
# time stamps. (candump gets a 32 MiB receive buffer: with the default one it drops frames under
# emulation.)
set -uo pipefail

script_dir=$(cd -- "$(dirname -- "${BASH_SOURCE[0]}")" && pwd -P)
repo=$(cd -- "${script_dir}/../.." && pwd -P)

# ---------------------------------------------------------------------------------------------
# The guest's part: six phases of traffic, each in ${work}/<phase>/ (candump.log, run.log,
# rig.log, out/, and `status`, the master's exit status).
in_guest() {
  local cambio=$1
  work=$2
  local rig_file=${repo}/firmware_config/rigs/pan_tilt.yaml
  local experiment=${repo}/firmware_config/experiments/pan_tilt_hold.yaml
  rig_pid='' dump_pid='' master_pid='' phase=''
  trap '[[ -n ${rig_pid} ]] && kill -CONT "${rig_pid}" 2>/dev/null && kill -INT "${rig_pid}" 2>/dev/null
        [[ -n ${dump_pid} ]] && kill "${dump_pid}" 2>/dev/null
        wait 2>/dev/null' EXIT

  local rig_sets=(--set groups.pan_tilt.backend=socketcan --set can_buses.can0.interface=vcan0)
  # A tiny camera at 5 Hz: the guest renders on an emulated CPU and the camera is not under test.
  local run_sets=(--set rig.groups.pan_tilt.backend=socketcan --set rig.can_buses.can0.interface=vcan0
    --set rig.cameras.camera.width_px=64 --set rig.cameras.camera.height_px=48
    --set rig.cameras.camera.focal_px=55 --set "rig.cameras.camera.principal_point_px=[31.5,23.5]"
    --set rig.loops.camera.rate_hz=5)

  # start_phase NAME [virtual-rig arguments...]: the emulated drives and a candump -L recorder.
  start_phase() {
    local name=$1
    shift
    phase=${work}/${name}
    mkdir -p "${phase}"
    candump -L -r 33554432 vcan0 >"${phase}/candump.log" &
    dump_pid=$!
    "${cambio}" virtual-rig --config "${rig_file}" "${rig_sets[@]}" "$@" >"${phase}/rig.log" 2>&1 &
    rig_pid=$!
    # The drives announce themselves with their boot-up (701#00, 702#00).
    for _ in $(seq 100); do grep -q '702#00$' "${phase}/candump.log" && break; sleep 0.1; done
  }
  # stop_dump FILE: candump runs behind under emulation; stop it once it has written everything.
  stop_dump() {
    local before=-1 now
    now=$(stat -c %s "$1")
    while [[ ${now} != "${before}" ]]; do
      before=${now}
      sleep 1
      now=$(stat -c %s "$1")
    done
    kill -INT "${dump_pid}" 2>/dev/null
    wait "${dump_pid}" 2>/dev/null
    dump_pid=
  }
  # end_phase: the master's exit status kept, the drives stopped, candump stopped once caught up.
  end_phase() {
    wait "${master_pid}"
    echo $? >"${phase}/status"
    kill -CONT "${rig_pid}" 2>/dev/null
    kill -INT "${rig_pid}" 2>/dev/null
    wait "${rig_pid}" 2>/dev/null
    rig_pid=
    stop_dump "${phase}/candump.log"
  }
  # run_master [cambio run arguments...]: `cambio run` in the background; sets master_pid.
  run_master() {
    "${cambio}" run "${experiment}" "${run_sets[@]}" --out "${phase}/out" "$@" \
      >"${phase}/run.log" 2>&1 &
    master_pid=$!
  }
  wait_enabled() {  # Until the master sends "enable operation" (controlword 0x000F) to node 2.
    for _ in $(seq 600); do grep -q ' 202#0F00' "${phase}/candump.log" && return 0; sleep 0.1; done
    return 1
  }

  # 1. Configure, enable, hold at 1 kHz, disable.
  start_phase traffic
  run_master --set experiment.duration_s=10 --can-log "${work}/traffic/master.log"
  end_phase

  # 2. canplayer replays the start of the master's log.
  phase=${work}/replay
  mkdir -p "${phase}"
  head -n 400 "${work}/traffic/master.log" >"${phase}/part.log"
  candump -L -r 33554432 vcan0 >"${phase}/candump.log" &
  dump_pid=$!
  sleep 0.3
  canplayer -t -I "${phase}/part.log" vcan0=vcan0
  stop_dump "${phase}/candump.log"

  # 3. A following-error fault in node 1 while enabled.
  start_phase following_error --fault following-error,node=1,after_enable_s=0.5
  run_master --set experiment.duration_s=4
  end_phase

  # 3b. The same fault with the experiment asking for recovery.
  start_phase recovery --fault following-error,node=1,after_enable_s=0.5
  run_master --set experiment.duration_s=4 --set experiment.fault_recovery.after_s=0.3 \
    --set experiment.fault_recovery.max_recoveries=1
  end_phase

  # 4. Heartbeat loss: the drives' process freezes; `frozen_s` is when, on the guest's clock
  # (candump's stamps are on the same clock).
  start_phase heartbeat_loss
  run_master --set experiment.duration_s=6
  if wait_enabled; then
    sleep 1
    kill -STOP "${rig_pid}"
    date +%s.%N >"${phase}/frozen_s"
  fi
  end_phase

  # 5. cansend as the peer: an EMCY (counted, reported) and a boot-up (a drive rebooted).
  start_phase cansend
  run_master --set experiment.duration_s=6
  if wait_enabled; then
    cansend vcan0 081#0073010000000000  # EMCY 0x7300 (sensor), no fault in the statusword
    sleep 1
    cansend vcan0 702#00  # Node 2 announces a boot-up: it rebooted and lost its configuration.
  fi
  end_phase

  # 6. SIGINT. The log is marked before the signal (`signal_line`): a master that stops quickly
  # has written its NMT frames by the time a count taken after the kill runs.
  start_phase sigint
  run_master --set experiment.duration_s=60
  if wait_enabled; then
    sleep 1
    wc -l <"${phase}/candump.log" >"${phase}/signal_line"
    kill -INT "${master_pid}"
  fi
  end_phase
}

if [[ ${1:-} == --in-guest ]]; then
  in_guest "${2:?}" "${3:?}"
  exit 0
fi

# ---------------------------------------------------------------------------------------------
# The host's part: run the guest, then judge what it left.
cambio=${1:?usage: can_stack_vm_test.sh CAMBIO}
build_dir=${CAMBIO_BUILD_DIR:-${repo}/build}
# Under the build directory (shared read-write with the guest), so a failure leaves its logs.
work=$(mktemp -d -p "${build_dir}" can_stack_vm_test.XXXXXX)
failures=0

say() { printf 'can_stack_vm_test: %s\n' "$*"; }
check() {  # check DESCRIPTION COMMAND...
  local what=$1
  shift
  if "$@"; then say "ok: ${what}"; else say "FAILED: ${what}"; failures=$((failures + 1)); fi
}
report_failure() {
  say "$*; logs in ${work}"
  for f in "${work}"/*/run.log "${work}"/*/rig.log; do
    [[ -f ${f} ]] && { echo "--- ${f}"; tail -n 15 "${f}"; }
  done
  exit 1
}

CAMBIO_BUILD_DIR=${build_dir} "${script_dir}/run_in_guest.sh" "${script_dir}/can_stack_vm_test.sh" \
  --in-guest "${cambio}" "${work}"
guest_status=$?
[[ ${guest_status} -eq 77 ]] && exit 77  # The guest cannot start here (run_in_guest.sh said why).
[[ ${guest_status} -eq 0 ]] || report_failure "the guest's part failed (exit ${guest_status})"

status_of() { cat "${work}/$1/status" 2>/dev/null || echo none; }
# Frames (ID#DATA) of the COB-IDs only a master sends: NMT, SYNC, RPDOs, SDO requests.
master_frames() {
  awk '{print $3}' "$1" | grep -E '^(000|080|2[0-7][0-9A-F]|3[0-7][0-9A-F]|6[0-7][0-9A-F])#'
}
# Seconds (float) of the first candump line matching REGEX after line AFTER_LINE (0 = start).
time_of() {
  awk -v re="$2" -v after="${3:-0}" 'NR > after && $3 ~ re {gsub(/[()]/, "", $1); print $1; exit}' "$1"
}
line_of() { grep -n -E "$2" "$1" | head -1 | cut -d: -f1; }
json_value() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

# --- 1. Configure, enable, hold at 1 kHz, disable: the traffic seen by candump -------------------
phase=${work}/traffic
status=$(status_of traffic)
log=${phase}/candump.log
check "pan-tilt over vcan0 completes (exit 0; got ${status})" test "${status}" -eq 0
check "NMT reset communication to node 1 (000#8201)" grep -q ' 000#8201$' "${log}"
check "SDO requests to both nodes and answers (601/602, 581/582)" \
  sh -c "grep -q ' 601#' '${log}' && grep -q ' 602#' '${log}' && grep -q ' 581#' '${log}' && grep -q ' 582#' '${log}'"
# TPDO1's COB-ID (0x1800:1) is 0x181 with bit 30 (no RTR); bit 31 marks it invalid while mapping.
invalid_line=$(line_of "${log}" ' 601#23001801810100C0$')
valid_line=$(line_of "${log}" ' 601#2300180181010040$')
check "TPDO1 mapped as CiA 301 says: COB-ID invalidated (line ${invalid_line}), then valid (${valid_line})" \
  test -n "${invalid_line}" -a -n "${valid_line}" -a "${invalid_line:-0}" -lt "${valid_line:-0}"
check "NMT start of node 2 (000#0102)" grep -q ' 000#0102$' "${log}"
check "SYNC (080#), RPDOs (201#, 202#) and TPDOs (181#, 182#) on the bus" \
  sh -c "grep -q ' 080#$' '${log}' && grep -q ' 201#' '${log}' && grep -q ' 202#' '${log}' && grep -q ' 181#' '${log}'"
check "drives enabled through shutdown, switch on, enable operation (0x06, 0x07, 0x0F)" \
  sh -c "grep -q ' 201#0600' '${log}' && grep -q ' 201#0700' '${log}' && grep -q ' 201#0F00' '${log}'"
last_rpdo=$(grep ' 201#' "${log}" | tail -1 | awk '{print $3}')
check "the last RPDO to node 1 disables it (controlword 0x0000; got ${last_rpdo})" \
  test "${last_rpdo:0:8}" = "201#0000"
check "nodes left pre-operational at the end (000#8001, 000#8002)" \
  sh -c "grep -q ' 000#8001$' '${log}' && grep -q ' 000#8002$' '${log}'"
# (Files, not <(...): the guest's /dev has no /dev/fd for process substitution.)
master_frames "${work}/traffic/master.log" >"${phase}/sent_by_master.txt"
master_frames "${log}" >"${phase}/sent_seen_by_candump.txt"
check "the master's --can-log has every frame it sent, in candump's order" \
  cmp -s "${phase}/sent_by_master.txt" "${phase}/sent_seen_by_candump.txt"
syncs=$(json_value "${phase}/out/summary.json" "d['can_groups']['pan_tilt']['syncs_sent']")
# Deactivation adds two SYNCs of its own (after the quick-stop and the disable RPDOs).
bus_syncs=$(grep -c ' 080#$' "${log}")
check "summary.json counts the loop's SYNCs (${syncs}); candump saw those + 2 ($(( bus_syncs )))" \
  test "${bus_syncs}" -eq $((syncs + 2))
say "pan-tilt 1 kHz for 10 s in the guest: $(json_value "${phase}/out/summary.json" \
  "', '.join(f'{k} {v}' for k, v in d['can_groups']['pan_tilt'].items())")"

# The CSP cycle as candump's kernel stamps saw it: from each SYNC to the last TPDO answering it.
python3 - "${log}" <<'PY'
import statistics, sys
latencies_us, sync_s, pending = [], None, set()
for line in open(sys.argv[1]):
    stamp, _, frame = line.split()
    t = float(stamp.strip("()"))
    cob = frame.split("#")[0]
    if cob == "080":
        sync_s, pending = t, {"181", "182"}
    elif sync_s is not None and cob in pending:
        pending.discard(cob)
        if not pending:
            latencies_us.append((t - sync_s) * 1e6)
            sync_s = None
if latencies_us:
    q = statistics.quantiles(latencies_us, n=100)
    print(f"can_stack_vm_test: SYNC -> all TPDOs (emulated guest, {len(latencies_us)} cycles): "
          f"p50 {q[49]:.0f} us, p99 {q[98]:.0f} us")
PY

# Homing as candump saw it: the pan (node 1, incremental encoder) homes with CiA 402 method 17
# (limit switch) before the first SYNC; the tilt (node 2, absolute) never enters homing mode.
check "node 1 homed (method 17, mode 6, start, statusword bits 12+10) before CSP and the first SYNC" \
  python3 - "${log}" <<'PY'
import sys
frames = []
for line in open(sys.argv[1]):
    stamp, _, frame = line.split()
    cob, _, data = frame.partition("#")
    frames.append((float(stamp.strip("()")), cob, data))
def first(pred, after=-1):
    return next((i for i, f in enumerate(frames) if i > after and pred(f)), None)
def sdo_write(node, index, value_hex):  # Expedited download of `value_hex` (LE bytes) at :00.
    head = f"{index & 0xFF:02X}{index >> 8:02X}00"
    return lambda f: (f[1] == f"{0x600 + node:03X}" and f[2][0:2] in ("2F", "2B", "27", "23")
                      and f[2][2:8] == head and f[2][8:].startswith(value_hex))
method = first(sdo_write(1, 0x6098, "11"))
mode6 = first(sdo_write(1, 0x6060, "06"))
start = first(sdo_write(1, 0x6040, "1F00"), mode6 if mode6 is not None else -1)
csp = first(sdo_write(1, 0x6060, "08"), start if start is not None else -1)
sync = first(lambda f: f[1] == "080")
words = []
for i in range(mode6 or 0, csp or len(frames)):
    t, cob, data = frames[i]
    if cob == "581" and data.startswith("4B416000"):
        word = int(data[10:12] + data[8:10], 16)
        if not words or words[-1][1] != word:
            words.append((t, word))
print("can_stack_vm_test: node 1 homing statuswords (SDO 0x6041 answers):",
      " -> ".join(f"{w:04X}" for _, w in words),
      f"in {words[-1][0] - frames[mode6][0]:.3f} s" if words and mode6 is not None else "")
ok = (None not in (method, mode6, start, csp, sync) and method < mode6 < start < csp < sync
      and words and words[-1][1] & 0x1400 == 0x1400 and not any(w & 0x2000 for _, w in words)
      and first(sdo_write(2, 0x6060, "06")) is None)
sys.exit(0 if ok else 1)
PY

# --- 2. canplayer replays the master's log --------------------------------------------------------
awk '{print $3}' "${work}/replay/part.log" >"${work}/replay/played.txt"
awk '{print $3}' "${work}/replay/candump.log" >"${work}/replay/seen.txt"
check "canplayer replays the master's log frame for frame" \
  cmp -s "${work}/replay/played.txt" "${work}/replay/seen.txt"

# --- 3. A following-error fault in node 1 while enabled ----------------------------------------
phase=${work}/following_error
status=$(status_of following_error)
log=${phase}/candump.log
check "a drive fault stops the run with exit 3 (got ${status})" test "${status}" -eq 3
check "summary.json says device_fault" \
  test "$(json_value "${phase}/out/summary.json" "d['outcome']")" = device_fault
emcy_line=$(line_of "${log}" ' 081#1186')
check "node 1 sent EMCY 0x8611 (following error)" test -n "${emcy_line}"
if [[ -n ${emcy_line} ]]; then
  t_fault=$(time_of "${log}" '^081#1186')
  t_stop=$(time_of "${log}" '^202#0200' "${emcy_line}")
  check "node 2 quick-stopped after node 1's fault, within 3 heartbeat periods (${t_fault} -> ${t_stop})" \
    python3 -c "import sys; sys.exit(0 if '${t_stop}' and float('${t_stop}') - float('${t_fault}') <= 0.3 else 1)"
  stop_line=$(tail -n +"${emcy_line}" "${log}" | grep -n ' 202#0200' | head -1 | cut -d: -f1)
  check "no enable-operation RPDO to node 2 once it was quick-stopped (no motion)" \
    sh -c "test -n '${stop_line}' && ! tail -n +$((emcy_line + ${stop_line:-0})) '${log}' | grep -q ' 202#0F00'"
fi

# --- 3b. The same fault with the experiment asking for recovery: reset, re-enable, no restart ---
phase=${work}/recovery
status=$(status_of recovery)
log=${phase}/candump.log
check "with fault_recovery the run recovers and completes (exit 0; got ${status})" \
  test "${status}" -eq 0
check "summary.json counts one recovery" \
  test "$(json_value "${phase}/out/summary.json" "d['joint_loop']['fault_recoveries']")" -eq 1
emcy_line=$(line_of "${log}" ' 081#1186')
if [[ -n ${emcy_line} ]]; then
  check "node 1 reset (EMCY 0x0000) and re-enabled (201#0F00) after its fault" \
    sh -c "tail -n +${emcy_line} '${log}' | grep -q ' 081#0000' && tail -n +${emcy_line} '${log}' | grep -q ' 201#0F00'"
fi

# --- 4. Heartbeat loss: the drives' process freezes -------------------------------------------------
phase=${work}/heartbeat_loss
status=$(status_of heartbeat_loss)
t_frozen=$(cat "${phase}/frozen_s" 2>/dev/null)
log=${phase}/candump.log
check "a lost drive stops the run with exit 3 (got ${status})" test "${status}" -eq 3
if [[ -n ${t_frozen:-} ]]; then
  last_heartbeat=$(awk -v t="${t_frozen}" '$3 ~ /^70[12]#/ {s = substr($1, 2, length($1) - 2) + 0; if (s <= t + 0.05) last = s} END {printf "%.6f", last}' "${log}")
  t_react=$(awk -v t="${last_heartbeat}" '$3 ~ /^20[12]#0[02]00/ {s = substr($1, 2, length($1) - 2) + 0; if (s > t) {printf "%.6f", s; exit}}' "${log}")
  check "comm loss latched within 3 heartbeat periods + one cycle (last heartbeat ${last_heartbeat}, hold ${t_react})" \
    python3 -c "import sys; sys.exit(0 if '${t_react}' and float('${t_react}') - float('${last_heartbeat}') <= 0.35 else 1)"
fi

# --- 5. cansend as the peer: an EMCY (counted, reported) and a boot-up (a drive rebooted) --------
phase=${work}/cansend
status=$(status_of cansend)
check "a rebooted drive (boot-up from cansend) stops the run with exit 3 (got ${status})" \
  test "${status}" -eq 3
check "the EMCY from cansend is counted in summary.json" \
  test "$(json_value "${phase}/out/summary.json" "d['can_groups']['pan_tilt']['emergencies']")" -ge 1

# --- 6. SIGINT: every drive disabled, nodes left pre-operational ----------------------------------
phase=${work}/sigint
status=$(status_of sigint)
signal_line=$(cat "${phase}/signal_line" 2>/dev/null)
log=${phase}/candump.log
check "SIGINT stops the run with exit 130 (got ${status})" test "${status}" -eq 130
for node in 1 2; do
  last=$(grep " 20${node}#" "${log}" | tail -1 | awk '{print $3}')
  check "node ${node}'s last controlword is disable voltage (${last})" test "${last:0:8}" = "20${node}#0000"
  check "node ${node} sent to pre-operational after SIGINT (000#800${node})" \
    sh -c "tail -n +${signal_line:-1} '${log}' | grep -q ' 000#800${node}$'"
done
preop_line=$(tail -n +"${signal_line:-1}" "${log}" | grep -n ' 000#800[12]$' | head -1 | cut -d: -f1)
check "no SYNC once the nodes are pre-operational" \
  sh -c "test -n '${preop_line}' && ! tail -n +$(( ${signal_line:-1} + ${preop_line:-0} )) '${log}' | grep -q ' 080#$'"

[[ ${failures} -eq 0 ]] || report_failure "${failures} check(s) failed"
say "all checks passed"
rm -rf "${work}"
