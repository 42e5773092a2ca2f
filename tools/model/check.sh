#!/usr/bin/env bash
# @file check.sh
# @brief Checks the TMR protocol's model (tools/model/tmr.pml) with SPIN: the clean runs must hold every
#        property, every seeded mutant and every recorded finding must be found, with its trail.
#
# Usage: tools/model/check.sh [quick|full] [OUT_DIR]   (default: quick, build/model)
#   quick  the runs of `make model` and CI: one fault of every kind at any release, the switch to TMR
#          and back under one fault, the mutants and the findings (runs side by side, one per core)
#   full   also the switch over a longer horizon and two faults at any releases (`make model-full`:
#          about 10 minutes and 10 GB)
# Each run gets OUT_DIR/<run>/: pan.out (SPIN's report), and for a run that found an error,
# trail.txt (the guided replay's events) and plan.toml (that trail as a fault plan, trail_to_plan.py).
# OUT_DIR/report.md tables every run: expected, result, states stored, memory, time.
# Exits 1 if a clean run finds an error or a mutant or finding is not found.
set -uo pipefail
mode=${1:-quick}
out=${2:-build/model}
here=$(cd "$(dirname "$0")" && pwd)
case "$mode" in quick|full) ;; *) echo "check.sh: unknown mode '$mode' (quick, full)" >&2; exit 2 ;; esac
command -v spin >/dev/null || { echo "check.sh: spin is missing (tools/build/deps.sh model)" >&2; exit 2; }
mkdir -p "$out"
# Memory for the state store: the full run's two faults take about 10 GB with -DCOLLAPSE.
pan_cc=(-DSAFETY -DCOLLAPSE -DMEMLIM=20000)

# name | expect (hold: no error; found: an error with its trail) | -D options | what it checks
# The clean runs are exhaustive over their bounds; a mutant's or finding's run stops at its first error.
runs=(
  "single|hold||one fault of any kind on the voter or a replica at any release from 2 to 8 (the switch to TMR at 1); P1-P7"
  "switch|hold|-DCMD_STOP=1 -DCMD_RETMR=1 -DSTOPPING_VOTER_FAULTS=0 -DHORIZON=18 -DFAULT_LAST=6|filter_simplex at any release, then filter_tmr again, one fault at 2..6 (none on the voter while it stops: F1); P1-P7"
  "mutant-deliver-early|found|-DMUTANT_DELIVER_EARLY|seeded: the first good output delivered before a second confirms it (P2)"
  "mutant-stop-no-replay|found|-DMUTANT_STOP_NO_REPLAY -DCMD_STOP=1 -DSTOPPING_VOTER_FAULTS=0|seeded: back to simplex without running the records since the stop job (P3)"
  "mutant-wait-forever|found|-DMUTANT_WAIT_FOREVER|seeded: a vote waits for every voting replica, with no end (P4, P6)"
  "finding-stop-reset|found|-DCMD_STOP=1|F1: the voter reset while it stops (P4)"
  "finding-reset-midjob|found|-DMIDJOB=1|F2: the voter reset between a delivery and the write of its place (P1)"
  "finding-reset-late|found|-DLATEJOB=1|F3: the voter reset after its job, booted in the same release (P4)"
  "finding-lenient|found|-DMAXF=2 -DHORIZON=18 -DFAULT_LAST=6|F4: a replica lost while a restarted voter waits for every output (P4, two faults)"
)
if [ "$mode" = full ]; then
  runs+=("switch-long|hold|-DCMD_STOP=1 -DCMD_RETMR=1 -DSTOPPING_VOTER_FAULTS=0|as switch, over 20 releases with faults at 2..8; P1-P7")
  runs+=("double|hold|-DMAXF=2 -DHORIZON=18 -DFAULT_LAST=6 -DP_NOSKIP=0 -DP_RECOVER=0 -DP_SWITCH=0|two faults of any kind at any releases from 2 to 6; P1 P2 P3 P6")
fi

# One run: verifier built and run in OUT_DIR/<name>; its line of the report in OUT_DIR/<name>/result.
check_one() {
  local name=$1 expect=$2 defs=$3 what=$4 dir="$out/$1" dflags cc w start ms secs rc errors states mem result
  rm -rf "$dir" && mkdir -p "$dir"
  cp "$here/tmr.pml" "$dir/"
  read -r -a dflags <<< "$defs"
  # A clean run searches millions of states: optimised, a big hash table. A search for an error is short.
  if [ "$expect" = hold ]; then cc=(-O2 "${pan_cc[@]}"); w=-w25; else cc=(-O0 "${pan_cc[@]}"); w=-w20; fi
  start=$(date +%s%N)
  ( cd "$dir" && spin -a "${dflags[@]}" tmr.pml >spin.out 2>&1 && gcc "${cc[@]}" -o pan pan.c 2>cc.out &&
    ./pan -m400000 "$w" >pan.out 2>&1 )
  rc=$?
  ms=$(( ($(date +%s%N) - start) / 1000000 ))
  secs=$((ms / 1000)).$(( (ms % 1000) / 100 ))
  errors=$(sed -n 's/.*errors: \([0-9]*\).*/\1/p' "$dir/pan.out" 2>/dev/null | tail -1)
  states=$(awk '/states, stored/ {print $1; exit}' "$dir/pan.out" 2>/dev/null)
  mem=$(awk '/total actual memory usage/ {print $1; exit}' "$dir/pan.out" 2>/dev/null)
  if [ -z "$errors" ]; then
    result="BROKEN (spin or pan failed, status $rc)"
  elif [ "$errors" -eq 0 ]; then
    [ "$expect" = hold ] && result="holds" || result="NOT FOUND"
  else
    ( cd "$dir" && spin -t "${dflags[@]}" tmr.pml 2>&1 | grep -E "MODEL|assert|violated" > trail.txt )
    if python3 "$here/trail_to_plan.py" "$dir/trail.txt" --name "model-$name" > "$dir/plan.toml"; then
      [ "$expect" = found ] && result="found" || result="VIOLATED"
    else
      result="found, NO PLAN"
    fi
  fi
  printf '%s|%s|%s|%s|%s|%s|%s\n' "$name" "$expect" "$result" "${states:-?}" "${mem:-?}" "$secs" "$what" > "$dir/result"
}

jobs=$(nproc 2>/dev/null || echo 2)
for r in "${runs[@]}"; do
  IFS='|' read -r name expect defs what <<< "$r"
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n; done
  check_one "$name" "$expect" "$defs" "$what" &
done
wait

status=0
report="$out/report.md"
{
  echo "| run | expected | result | states stored | memory (MB) | time (s) | what it checks |"
  echo "|---|---|---|---|---|---|---|"
} > "$report"
for r in "${runs[@]}"; do
  IFS='|' read -r name _ <<< "$r"
  dir="$out/$name"
  IFS='|' read -r name expect result states mem secs what < "$dir/result"
  case "$result" in holds|found) ;; *) status=1 ;; esac
  printf 'model: %-24s %-6s %-10s %12s states %9s MB %7s s\n' "$name" "$expect" "$result" "$states" "$mem" "$secs"
  if [ -f "$dir/trail.txt" ]; then
    grep -E "MODEL (fault|event|skipped)|failed assertion" "$dir/trail.txt" | sed 's/^ */    /'
  fi
  if [ "$result" != holds ] && [ "$result" != found ]; then
    cat "$dir/spin.out" "$dir/cc.out" "$dir/pan.out" 2>/dev/null | head -20
  fi
  printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$name" "$expect" "$result" "$states" "$mem" "$secs" "$what" >> "$report"
done
echo "model: report in $report"
[ "$status" -eq 0 ] && echo "model: every clean run holds; every mutant and finding was found" ||
  echo "model: FAILED"
exit "$status"
