#!/usr/bin/env bash
# @file run_tests.sh
# @brief Runs every GoogleTest binary, then prints one line: "tests: N passed, N failed, N skipped".
#
# Usage: run_tests.sh RESULTS_DIR TEST_BINARY...
# Binaries run TEST_JOBS at a time (default: the machine's CPUs); the mission
# suite, which flies whole descents, is split into GoogleTest shards so both
# cores fly. The jobs start longest first (the wall times of the last run, kept
# in RESULTS_DIR/durations; without them the flights first), so that no long
# job starts last beside an idle core. Every test is deterministic (emulated
# time only), so running them side by side, in any order, changes nothing but
# the wall time. TEST_FILTERS="BINARY=PATTERN ..." runs only the tests of
# BINARY (its file name) that match the GoogleTest filter PATTERN (the
# sanitizer stage of CI flies a subset this way, mk/flight_subset.mk). Each
# binary's output is printed in the order given once all have run, with its
# wall time. Counts come from each job's
# XML report, test case by test case (tools/build/count_tests.py). A binary
# that dies without a readable report counts as one failure, and so does a
# binary that ran no test at all. A skipped test is a test that did not run:
# it is named and fails the run (no test skips on purpose; one that cannot
# make its condition says why and fails).
# Exit status is non-zero on any failure or skip.
set -uo pipefail
results=$1; shift
mkdir -p "$results"
# Reports of an earlier run (other binaries, other shard counts) would be read as this one's.
rm -f "$results"/*.xml "$results"/*.rc "$results"/*.log "$results"/*.wall "$results"/*.count.err
jobs=${TEST_JOBS:-$(nproc 2>/dev/null || echo 1)}
[ "$jobs" -ge 1 ] 2>/dev/null || jobs=1

shards_of() {  # shards_of BINARY: how many shards its tests are split into
  case "$(basename "$1")" in
    tools_trn_mission_tests) echo 6 ;;
    tools_trn_campaign_tests) echo 2 ;;
    *) echo 1 ;;
  esac
}

filter_of() {  # filter_of BINARY: its GoogleTest filter from TEST_FILTERS, or nothing
  local name f
  name=$(basename "$1")
  for f in ${TEST_FILTERS:-}; do
    if [ "${f%%=*}" = "$name" ]; then echo "${f#*=}"; return; fi
  done
}

# Seconds each job took in the last run ("NAME SHARD SECONDS" lines), to start the longest first.
durations="$results/durations"
declare -A last_wall=()
if [ -r "$durations" ]; then
  while read -r n sh sec; do last_wall["$n/$sh"]=$sec; done < "$durations"
fi
weight_of() {  # weight_of NAME SHARD: the job's expected seconds; unknown: the flights first
  local w=${last_wall["$1/$2"]:-}
  if [ -n "$w" ]; then echo "$w"; return; fi
  case "$1" in
    tools_trn_mission_tests|tools_trn_campaign_tests) echo 1000 ;;
    *) echo 0 ;;
  esac
}

here=$(cd "$(dirname "$0")" && pwd)

# The jobs: one per binary, or one per shard.
bins=(); shard=(); total=()
for bin in "$@"; do
  n=$(shards_of "$bin")
  for ((s = 0; s < n; s++)); do
    bins+=("$bin"); shard+=("$s"); total+=("$n")
  done
done

run_job() {  # run_job INDEX: runs one job, its output, report and status under $results/INDEX-NAME.*
  local k=$1 bin=${bins[$1]} tag start filter args=()
  tag="$k-$(basename "$bin")"
  rm -f "$results/$tag.xml" "$results/$tag.rc"
  filter=$(filter_of "$bin")
  [ -z "$filter" ] || args+=("--gtest_filter=$filter")
  start=$(date +%s)
  if [ "${total[$k]}" -gt 1 ]; then
    GTEST_TOTAL_SHARDS=${total[$k]} GTEST_SHARD_INDEX=${shard[$k]} \
      "$bin" "${args[@]}" --gtest_output="xml:$results/$tag.xml" --gtest_brief=1 > "$results/$tag.log" 2>&1
  else
    "$bin" "${args[@]}" --gtest_output="xml:$results/$tag.xml" --gtest_brief=1 > "$results/$tag.log" 2>&1
  fi
  echo $? > "$results/$tag.rc"
  echo $(($(date +%s) - start)) > "$results/$tag.wall"
}

# Longest first; equal weights keep the order given.
mapfile -t order < <(for ((k = 0; k < ${#bins[@]}; k++)); do
  echo "$(weight_of "$(basename "${bins[$k]}")" "${shard[$k]}") $k"
done | sort -s -k1,1nr | cut -d' ' -f2)

running=0
for k in "${order[@]}"; do
  run_job "$k" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n
    running=$((running - 1))
  fi
done
wait

passed=0; failed=0; skipped=0; broken=(); skipped_names=()
declare -A ran_by_bin=()
names=()
for ((k = 0; k < ${#bins[@]}; k++)); do
  name=$(basename "${bins[$k]}")
  tag="$k-$name"
  xml="$results/$tag.xml"
  wall=$(cat "$results/$tag.wall" 2>/dev/null || echo "?")
  if [ "${total[$k]}" -gt 1 ]; then
    echo "=== $name (shard $((shard[k] + 1)) of ${total[$k]}, ${wall} s)"
  else
    echo "=== $name (${wall} s)"
  fi
  tail -n 200 "$results/$tag.log"
  rc=$(cat "$results/$tag.rc" 2>/dev/null || echo 255)
  counts=""
  [ -s "$xml" ] && counts=$(python3 "$here/count_tests.py" "$xml" 2>"$results/$tag.count.err")
  if [ -z "$counts" ]; then
    if [ -s "$xml" ]; then
      echo "!!! $name exited with status $rc and its report cannot be read: $(head -c 300 "$results/$tag.count.err")"
    else
      echo "!!! $name exited with status $rc and wrote no report"
    fi
    failed=$((failed + 1)); broken+=("$name"); continue
  fi
  read -r p f s <<<"$(head -n1 <<<"$counts")"
  while IFS= read -r line; do skipped_names+=("$line"); done < <(tail -n +2 <<<"$counts")
  passed=$((passed + p)); failed=$((failed + f)); skipped=$((skipped + s))
  [ -n "${ran_by_bin[$name]+x}" ] || names+=("$name")
  ran_by_bin[$name]=$(( ${ran_by_bin[$name]:-0} + p + f + s ))
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
    echo "!!! $name exited with status $rc although no test failed"
    failed=$((failed + 1)); broken+=("$name")
  fi
done
# A binary that ran no test (an empty suite, a filter that matches nothing) tested nothing; a filter of
# whole names (no wildcard) that ran fewer tests than it names holds a name no test has (renamed).
for name in "${names[@]}"; do
  if [ "${ran_by_bin[$name]}" -eq 0 ]; then
    echo "!!! $name ran no test"
    failed=$((failed + 1)); broken+=("$name")
    continue
  fi
  filter=$(filter_of "$name")
  if [ -n "$filter" ] && [[ "$filter" != *[*?-]* ]]; then
    named=$(tr ':' '\n' <<<"$filter" | grep -c .)
    if [ "${ran_by_bin[$name]}" -ne "$named" ]; then
      echo "!!! $name ran ${ran_by_bin[$name]} of the $named tests its filter names: a name no test has"
      failed=$((failed + 1)); broken+=("$name")
    fi
  fi
done
# This run's wall times, for the next run's order.
for ((k = 0; k < ${#bins[@]}; k++)); do
  w=$(cat "$results/$k-$(basename "${bins[$k]}").wall" 2>/dev/null) || continue
  echo "$(basename "${bins[$k]}") ${shard[$k]} $w"
done > "$durations.tmp" && mv -f "$durations.tmp" "$durations"
[ ${#broken[@]} -eq 0 ] || echo "broken binaries: ${broken[*]}"
for n in "${skipped_names[@]}"; do echo "!!! skipped: $n"; done
echo "tests: $passed passed, $failed failed, $skipped skipped"
[ "$failed" -eq 0 ] && [ "$skipped" -eq 0 ]
