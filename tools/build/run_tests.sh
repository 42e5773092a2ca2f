#!/usr/bin/env bash
# @file run_tests.sh
# @brief Runs every GoogleTest binary, then prints one line: "tests: N passed, N failed".
#
# Usage: run_tests.sh RESULTS_DIR TEST_BINARY...
# Binaries run TEST_JOBS at a time (default: the machine's CPUs); the mission
# suite, which flies whole descents, is split into GoogleTest shards so both
# cores fly. Every test is deterministic (emulated time only), so running them
# side by side changes nothing but the wall time. Each binary's output is
# printed in the order given once all have run. Counts come from each job's
# XML report. A binary that dies without a report counts as one failure.
# Exit status is non-zero on any failure.
set -uo pipefail
results=$1; shift
mkdir -p "$results"
# Reports of an earlier run (other binaries, other shard counts) would be read as this one's.
rm -f "$results"/*.xml "$results"/*.rc "$results"/*.log
jobs=${TEST_JOBS:-$(nproc 2>/dev/null || echo 1)}
[ "$jobs" -ge 1 ] 2>/dev/null || jobs=1

shards_of() {  # shards_of BINARY: how many shards its tests are split into
  case "$(basename "$1")" in
    tools_trn_mission_tests) echo 4 ;;
    *) echo 1 ;;
  esac
}

attr() {  # attr NAME FILE: value of NAME on the root <testsuites> element
  sed -n 's/.*<testsuites[^>]*[[:space:]]'"$1"'="\([0-9]*\)".*/\1/p' "$2" | head -n1
}

# The jobs: one per binary, or one per shard.
bins=(); shard=(); total=()
for bin in "$@"; do
  n=$(shards_of "$bin")
  for ((s = 0; s < n; s++)); do
    bins+=("$bin"); shard+=("$s"); total+=("$n")
  done
done

run_job() {  # run_job INDEX: runs one job, its output, report and status under $results/INDEX-NAME.*
  local k=$1 bin=${bins[$1]} tag
  tag="$k-$(basename "$bin")"
  rm -f "$results/$tag.xml" "$results/$tag.rc"
  if [ "${total[$k]}" -gt 1 ]; then
    GTEST_TOTAL_SHARDS=${total[$k]} GTEST_SHARD_INDEX=${shard[$k]} \
      "$bin" --gtest_output="xml:$results/$tag.xml" --gtest_brief=1 > "$results/$tag.log" 2>&1
  else
    "$bin" --gtest_output="xml:$results/$tag.xml" --gtest_brief=1 > "$results/$tag.log" 2>&1
  fi
  echo $? > "$results/$tag.rc"
}

running=0
for ((k = 0; k < ${#bins[@]}; k++)); do
  run_job "$k" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n
    running=$((running - 1))
  fi
done
wait

passed=0; failed=0; skipped=0; broken=()
for ((k = 0; k < ${#bins[@]}; k++)); do
  name=$(basename "${bins[$k]}")
  tag="$k-$name"
  xml="$results/$tag.xml"
  if [ "${total[$k]}" -gt 1 ]; then
    echo "=== $name (shard $((shard[k] + 1)) of ${total[$k]})"
  else
    echo "=== $name"
  fi
  tail -n 200 "$results/$tag.log"
  rc=$(cat "$results/$tag.rc" 2>/dev/null || echo 255)
  if [ ! -s "$xml" ]; then
    echo "!!! $name exited with status $rc and wrote no report"
    failed=$((failed + 1)); broken+=("$name"); continue
  fi
  t=$(attr tests "$xml"); f=$(attr failures "$xml"); d=$(attr disabled "$xml"); s=$(attr skipped "$xml")
  e=$(attr errors "$xml")
  t=${t:-0}; f=${f:-0}; d=${d:-0}; s=${s:-0}; e=${e:-0}
  run=$((t - d - s))
  passed=$((passed + run - f - e)); failed=$((failed + f + e)); skipped=$((skipped + s))
  if [ "$rc" -ne 0 ] && [ $((f + e)) -eq 0 ]; then
    echo "!!! $name exited with status $rc although no test failed"
    failed=$((failed + 1)); broken+=("$name")
  fi
done
[ ${#broken[@]} -eq 0 ] || echo "broken binaries: ${broken[*]}"
if [ "$skipped" -gt 0 ]; then
  echo "tests: $passed passed, $failed failed, $skipped skipped"
else
  echo "tests: $passed passed, $failed failed"
fi
[ "$failed" -eq 0 ]
