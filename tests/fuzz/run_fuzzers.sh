#!/usr/bin/env bash
# Builds the fuzz targets with clang's libFuzzer, AddressSanitizer and UndefinedBehaviorSanitizer
# in build-fuzz/, and runs every bin/fuzz_* it built for SECONDS each (README.md).
#
#   bash tests/fuzz/run_fuzzers.sh SECONDS [TARGET...]
#
# TARGET names limit the run (e.g. fuzz_rig). Fails if any target crashes, leaks, runs out of
# time on one input or allocates more than the limits below; the input is left in
# build-fuzz/artifacts/ (README.md says how to reproduce it and keep it as a regression).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

if [[ $# -lt 1 || ! $1 =~ ^[0-9]+$ ]]; then
  echo "usage: bash tests/fuzz/run_fuzzers.sh SECONDS [TARGET...]" >&2
  exit 2
fi
seconds=$1
shift
build=build-fuzz
jobs=${CAMBIO_BUILD_JOBS:-2}

# Bounds that make a finding of what the loaders promise to keep bounded: one allocation above
# 1 GiB or a process above 2 GiB is reported as a crash, and so is one input taking 30 s.
fuzz_options=(-rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=30 -print_final_stats=1)

export CC=clang CXX=clang++
cmake -S . -B "$build" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAMBIO_FUZZ=ON -DCAMBIO_BUILD_TESTS=OFF \
  -DCAMBIO_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target fuzzers

# The seeds of a target: the shipped files of its kind, else tests/fuzz/seeds/<name>/.
seeds_of() {
  case $1 in
    fuzz_rig) echo firmware_config/rigs/*.yaml ;;
    fuzz_scene) echo firmware_config/scenes/*.yaml ;;
    fuzz_experiment) echo firmware_config/experiments/*.yaml ;;
    fuzz_perception) echo firmware_config/perception/*.yaml ;;
    *) [[ -d tests/fuzz/seeds/${1#fuzz_} ]] && echo tests/fuzz/seeds/"${1#fuzz_}"/* ;;
  esac
}

# A dictionary of every key the shipped files use, and YAML's punctuation: mutations that splice
# whole keys reach the loaders' checks sooner than byte flips do.
dictionary=$build/config.dict
{
  grep -rhoE '^[[:space:]-]*[a-z_0-9]+:' firmware_config --include='*.yaml' |
    sed -E 's/^[[:space:]-]*//' | sort -u | sed -E 's/(.*)/"\1"/'
  printf '"%s"\n' '---' '...' '&a ' '*a' '!!str ' '? ' ': ' '- ' '[' ']' '{' '}' ', ' '|' '>' \
    '#' "'" '\"' '_deg' '_rad' '1e308' '-1' '0' 'true' 'null' '.inf' '.nan'
} >"$dictionary"

shopt -s nullglob
targets=("$@")
if [[ ${#targets[@]} -eq 0 ]]; then
  for path in "$build"/bin/fuzz_*; do targets+=("$(basename "$path")"); done
fi
if [[ ${#targets[@]} -eq 0 ]]; then
  echo "run_fuzzers: no bin/fuzz_* was built" >&2
  exit 1
fi

mkdir -p "$build/artifacts" "$build/logs"

# Fuzzes one target for the set time; its summary line goes to logs/<target>.result, then
# " -- FAILED" and the sanitizer's findings when the target crashed.
run_target() {
  local target=$1 status=0
  local corpus=$build/corpus/$target seeds=$build/seeds/$target log=$build/logs/$target.log
  local result=$build/logs/$target.result
  rm -rf "$seeds"
  mkdir -p "$corpus" "$seeds"
  for seed in $(seeds_of "$target"); do cp "$seed" "$seeds/"; done
  local dict=()
  case $target in
    fuzz_rig | fuzz_scene | fuzz_experiment | fuzz_perception | fuzz_override)
      dict=(-dict="$dictionary") ;;
  esac
  # The corpus folder first: libFuzzer keeps the inputs that reach new code there, across runs.
  ASAN_OPTIONS=detect_leaks=1:leak_check_at_exit=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$build/bin/$target" "${fuzz_options[@]}" "${dict[@]}" -max_total_time="$seconds" \
    -artifact_prefix="$build/artifacts/$target-" "$corpus" "$seeds" >"$log" 2>&1 || status=$?
  # A target that crashed at once prints no statistics: those stay "?".
  local runs rate cov features
  runs=$(sed -nE 's/^stat::number_of_executed_units: *([0-9]+)/\1/p' "$log" | tail -1 || true)
  rate=$(sed -nE 's/^stat::average_exec_per_sec: *([0-9]+)/\1/p' "$log" | tail -1 || true)
  cov=$(grep -oE 'cov: [0-9]+' "$log" | tail -1 | cut -d' ' -f2 || true)
  features=$(grep -oE 'ft: [0-9]+' "$log" | tail -1 | cut -d' ' -f2 || true)
  local line="$target: ${runs:-?} runs, ${rate:-?} exec/s, cov ${cov:-?}, ft ${features:-?}"
  [[ $status -eq 0 ]] || line+=" -- FAILED (exit $status)"
  {
    echo "$line"
    if [[ $status -ne 0 ]]; then
      grep -E '^==[0-9]+==ERROR|^SUMMARY|runtime error|fuzz: a config|out-of-memory|Test unit written' \
        "$log" | head -20 || true
    fi
  } >"$result"
}

# libFuzzer runs one process per target: as many targets at once as there are build jobs, so
# every target still gets its full time on a core. An earlier run's results must not stand in
# for a target that dies before writing its own.
rm -f "$build"/logs/*.result
for target in "${targets[@]}"; do
  while [[ $(jobs -rp | wc -l) -ge $jobs ]]; do wait -n || true; done
  echo "=== $target: ${seconds} s (log: $build/logs/$target.log)"
  run_target "$target" &
done
wait

failed=()
summary=()
for target in "${targets[@]}"; do
  result=$build/logs/$target.result
  if [[ ! -s $result ]]; then
    echo "$target: no result -- FAILED" >"$result"
  fi
  cat "$result"
  line=$(head -1 "$result")
  summary+=("$line")
  [[ $line == *FAILED* ]] && failed+=("$target")
done

echo
echo "=== fuzzing summary (${seconds} s per target)"
printf '%s\n' "${summary[@]}"
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "run_fuzzers: ${failed[*]} failed; inputs in $build/artifacts/, logs in $build/logs/" >&2
  exit 1
fi
