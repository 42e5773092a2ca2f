#!/usr/bin/env bash
# @file run_tests.sh
# @brief Runs every GoogleTest binary, then prints one line: "tests: N passed, N failed".
#
# Usage: run_tests.sh RESULTS_DIR TEST_BINARY...
# Counts come from each binary's XML report. A binary that dies without a
# report counts as one failure. Exit status is non-zero on any failure.
set -uo pipefail
results=$1; shift
mkdir -p "$results"
passed=0; failed=0; skipped=0; broken=()

attr() {  # attr NAME FILE: value of NAME on the root <testsuites> element
  sed -n 's/.*<testsuites[^>]*[[:space:]]'"$1"'="\([0-9]*\)".*/\1/p' "$2" | head -n1
}

for bin in "$@"; do
  name=$(basename "$bin")
  xml="$results/$name.xml"
  rm -f "$xml"
  echo "=== $name"
  "$bin" --gtest_output="xml:$xml" --gtest_brief=1 2>&1 | tail -n 200
  rc=${PIPESTATUS[0]}
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
