#!/usr/bin/env bash
# Issue figure: the 1 kHz loop's p99 wake-up latency against cyclictest's, measured side by side.
# Runs PAIRS pairs; in each, `cambio loop-bench --rate-hz 1000` and
# `cyclictest -m -p 80 -i 1000 -l N -q` run at the same time. cyclictest gets a histogram
# (-h, which does not change what it measures) so its p99 can be read. Prints one JSON object
# with every pair and the median ratio. Needs rt-tests (apt-get install rt-tests) and python3.
#
#   bash bench/loop_latency_vs_cyclictest.sh [PAIRS=5] [DURATION_S=10]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cambio=${CAMBIO:-$root/build/bin/cambio}
pairs=${1:-5}
duration_s=${2:-10}
loops=$((duration_s * 1000))
command -v cyclictest >/dev/null || { echo "cyclictest missing: apt-get install rt-tests" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

for i in $(seq 1 "$pairs"); do
  cyclictest -m -p 80 -i 1000 -l "$loops" -q -h 20000 --histfile="$work/cyclic_$i.txt" >/dev/null &
  cyclic_pid=$!
  "$cambio" loop-bench --rate-hz 1000 --duration-s "$duration_s" --json >"$work/cambio_$i.json"
  wait "$cyclic_pid"
done

python3 - "$work" "$pairs" <<'PY'
import json, statistics, sys
work, pairs = sys.argv[1], int(sys.argv[2])

def cyclictest_percentiles(path):
    counts, overflow, max_us = {}, 0, 0
    for line in open(path):
        if line.startswith("# Histogram Overflows:"):
            overflow = int(line.split(":")[1].split()[0])
        elif line.startswith("# Max Latencies:"):
            max_us = int(line.split(":")[1].split()[0])
        elif line[:1].isdigit():
            us, n = line.split()[:2]
            counts[int(us)] = int(n)
    total = sum(counts.values()) + overflow
    def pct(f):
        rank, seen = f * total, 0
        for us in sorted(counts):
            seen += counts[us]
            if seen >= rank:
                return us + 1  # bucket upper edge, as cambio reports
        return max_us
    return {"p50_us": pct(0.50), "p99_us": pct(0.99), "p999_us": pct(0.999), "max_us": max_us}

rows = []
for i in range(1, pairs + 1):
    cambio = json.load(open(f"{work}/cambio_{i}.json"))["loops"][0]
    cyclic = cyclictest_percentiles(f"{work}/cyclic_{i}.txt")
    rows.append({"cambio_p50_us": cambio["p50_us"], "cambio_p99_us": cambio["p99_us"],
                 "cambio_max_us": cambio["max_us"], "cambio_overruns": cambio["overruns"],
                 "cambio_allocations_per_cycle": cambio["allocations_per_cycle"],
                 "cyclictest_p50_us": cyclic["p50_us"], "cyclictest_p99_us": cyclic["p99_us"],
                 "cyclictest_max_us": cyclic["max_us"],
                 "p99_ratio": cambio["p99_us"] / max(cyclic["p99_us"], 1)})
print(json.dumps({"pairs": rows,
                  "median_p99_ratio": statistics.median(r["p99_ratio"] for r in rows),
                  "median_cambio_p99_us": statistics.median(r["cambio_p99_us"] for r in rows),
                  "median_cyclictest_p99_us": statistics.median(r["cyclictest_p99_us"] for r in rows),
                  "goal": "median p99 ratio <= 1.2"}, indent=1))
PY
