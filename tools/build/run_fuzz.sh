#!/usr/bin/env bash
# @file run_fuzz.sh
# @brief Runs the libFuzzer targets one after the other (mk/fuzz.mk: `make fuzz`), prints each
#        one's executions, time and corpus, and fails on the first crash, hang, leak or
#        property violation.
#
# Usage: run_fuzz.sh SECONDS TOTAL_RUNS TIMEOUT MAX_LEN TARGET...
#   SECONDS     the longest a target runs
#   TOTAL_RUNS  executions to reach over all targets (empty: every target runs SECONDS):
#               each target is given an equal share of what is still missing, so what
#               a slow target does not reach within SECONDS falls to the ones after it
#               (list the fast ones last)
# Each target starts from the corpus in the repo (tests/fuzz/corpus/<name>/, read only) and
# the one that grows under build/fuzz/corpus/<name>/. Summary: build/fuzz/summary.txt.
set -uo pipefail
seconds=$1 total=$2 timeout=$3 max_len=$4; shift 4
targets=("$@")
out=build/fuzz
summary=$out/summary.txt
: >"$summary"
done_runs=0
left=${#targets[@]}
for t in "${targets[@]}"; do
  mkdir -p "$out/corpus/$t" "$out/artifacts/$t"
  limit=(-max_total_time="$seconds")
  if [ -n "$total" ]; then
    missing=$(( total > done_runs ? total - done_runs : 0 ))
    share=$(( (missing + left - 1) / left ))
    limit+=(-runs="$(( share > 0 ? share : 1 ))")
  fi
  seeds=()
  [ -d "tests/fuzz/corpus/$t" ] && seeds=("tests/fuzz/corpus/$t")
  echo "=== fuzz $t: ${limit[*]} (log: $out/$t.log)"
  start=$(date +%s)
  # ASan's leak detection is on by default for libFuzzer targets (-detect_leaks=1).
  if ! "$out/$t" "${limit[@]}" -timeout="$timeout" -max_len="$max_len" -detect_leaks=1 -print_final_stats=1 \
      -artifact_prefix="$out/artifacts/$t/" "$out/corpus/$t" "${seeds[@]}" >"$out/$t.log" 2>&1; then
    tail -n 60 "$out/$t.log"
    echo "fuzz: $t FAILED (the input is in $out/artifacts/$t/)"
    exit 1
  fi
  secs=$(( $(date +%s) - start ))
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/$t.log")
  corpus=$(find "$out/corpus/$t" -type f | wc -l)
  printf '%-20s %12s executions %6s s  corpus %6s inputs\n' "$t" "$runs" "$secs" "$corpus" | tee -a "$summary"
  done_runs=$(( done_runs + runs ))
  left=$(( left - 1 ))
done
echo "fuzz: $done_runs executions in total over ${#targets[@]} targets, no crash, hang or leak" | tee -a "$summary"
