#!/usr/bin/env bash
# Issue figure: the vergence experiment with its perception on another "machine", and a cut of
# the link. Two network namespaces joined by a veth pair stand for the robot and the perception
# host (Cyclone on the veth alone through firmware_config/ros2/cyclonedds_peer.xml, no
# multicast). RUNS runs of `cambio run vergence_sphere.yaml` with ros2.split: perception_remote
# against `cambio node perception`, then CUTS runs of 4 s with the robot's veth down for 1 s from
# 0.8 s in. Prints one JSON object: per run the goals, the pairs sent and results used, the
# exposure-to-result latency and the outages; the medians. Needs root, iproute2 and python3.
#
#   sudo bash bench/split_run_bench.sh [RUNS=5] [CUTS=3]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cambio=${CAMBIO:-$root/build/bin/cambio}
runs=${1:-5}
cuts=${2:-3}
experiment=$root/firmware_config/experiments/vergence_sphere.yaml
[ "$(id -u)" = 0 ] || { echo "split_run_bench: needs root (ip netns)" >&2; exit 2; }
work=$(mktemp -d)
tag=$$
robot=cambio_bench_robot_$tag
host=cambio_bench_host_$tag
cleanup() {
  ip netns del "$robot" 2>/dev/null || true
  ip netns del "$host" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
ip netns add "$robot"
ip netns add "$host"
ip link add "br$tag" type veth peer name "bh$tag"
ip link set "br$tag" netns "$robot"
ip link set "bh$tag" netns "$host"
ip -n "$robot" addr add 10.231.11.1/24 dev "br$tag"
ip -n "$host" addr add 10.231.11.2/24 dev "bh$tag"
for space in "$robot" "$host"; do ip -n "$space" link set lo up; done
ip -n "$robot" link set "br$tag" up
ip -n "$host" link set "bh$tag" up
in_robot=(ip netns exec "$robot" env "CYCLONEDDS_URI=file://$root/firmware_config/ros2/cyclonedds_peer.xml"
          "CAMBIO_DDS_INTERFACE=br$tag" CAMBIO_DDS_PEER=10.231.11.2)
in_host=(ip netns exec "$host" env "CYCLONEDDS_URI=file://$root/firmware_config/ros2/cyclonedds_peer.xml"
         "CAMBIO_DDS_INTERFACE=bh$tag" CAMBIO_DDS_PEER=10.231.11.1)

# One run: NAME DURATION_S CUT (0 or 1).
run_one() {
  local name=$1 duration_s=$2 cut=$3
  "${in_host[@]}" "$cambio" node perception "$experiment" --domain 93 >"$work/$name.node.log" 2>&1 &
  local node=$!
  "${in_robot[@]}" "$cambio" run "$experiment" --set experiment.executor=realtime \
    --set "experiment.duration_s=$duration_s" \
    --set 'experiment.ros2={domain_id: 93, split: perception_remote, images_hz: 0}' \
    --out "$work/$name" >"$work/$name.log" 2>&1 &
  local run=$!
  if [ "$cut" = 1 ]; then
    # Progress lines come every tenth of the run: 20% of 4 s is 0.8 s in.
    until grep -q "run:  20%" "$work/$name.log" || ! kill -0 "$run" 2>/dev/null; do sleep 0.02; done
    ip -n "$robot" link set "br$tag" down
    sleep 1
    ip -n "$robot" link set "br$tag" up
  fi
  local status=0
  wait "$run" || status=$?
  kill -TERM "$node" 2>/dev/null || true
  wait "$node" 2>/dev/null || true
  echo "$status" >"$work/$name.status"
}

for i in $(seq 1 "$runs"); do run_one "run_$i" 2 0; done
for i in $(seq 1 "$cuts"); do run_one "cut_$i" 4 1; done

python3 - "$work" "$runs" "$cuts" <<'PY'
import json, statistics, sys
work, runs, cuts = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])

def one(name):
    status = int(open(f"{work}/{name}.status").read())
    try:
        summary = json.load(open(f"{work}/{name}/summary.json"))
    except OSError:
        return {"name": name, "exit_status": status, "error": "no summary.json"}
    link = summary.get("perception_link", {})
    metrics = summary.get("metrics", {})
    return {"name": name, "exit_status": status, "goals_met": summary.get("passed"),
            "settle_time_s": metrics.get("settle_time_s"),
            "true_gaze_error_deg": metrics.get("true_gaze_error_deg"),
            "pairs_sent": link.get("pairs_sent"), "results_used": link.get("results_used"),
            "results_stale": link.get("results_stale"),
            "latency_median_ms": link.get("latency_median_ms"),
            "latency_max_ms": link.get("latency_max_ms"), "outages": link.get("outages")}

def median_of(rows, key):
    values = [r[key] for r in rows if isinstance(r.get(key), (int, float))]
    return statistics.median(values) if values else None

plain = [one(f"run_{i}") for i in range(1, runs + 1)]
cut = [one(f"cut_{i}") for i in range(1, cuts + 1)]
print(json.dumps({
    "runs": plain, "cut_runs": cut,
    "median_latency_ms": median_of(plain, "latency_median_ms"),
    "median_settle_time_s": median_of(plain, "settle_time_s"),
    "results_used_of_pairs_sent": [sum(r.get("results_used") or 0 for r in plain),
                                   sum(r.get("pairs_sent") or 0 for r in plain)],
    "goals_met": sum(1 for r in plain + cut if r.get("goals_met")),
    "runs_total": len(plain) + len(cut)}, indent=1))
PY
