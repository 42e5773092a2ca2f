#!/usr/bin/env bash
# @file run_bench.sh
# @brief `make bench`: runs every benchmark binary, JSON results under build/bench/.
set -euo pipefail
bin=$1; shift
out=build/bench
mkdir -p "$out"
if [ $# -eq 0 ]; then echo "bench: no benchmark binaries yet"; exit 0; fi
for b in "$@"; do
  name=$(basename "$b")
  echo "=== $name"
  "$b" --benchmark_out="$out/$name.json" --benchmark_out_format=json | tee "$out/$name.txt"
done
# Whole-run figure: the mission image over the whole descent, default scenario,
# no faults; its summary.json (real-time factor, errors) is the result. The
# closing summary (bench_summary.py) puts the vision and speed figures together.
if [ -x "$bin/trn_mission" ]; then
  echo "=== trn_mission (whole descent)"
  "$bin/trn_mission" --quiet --out "$out/mission_run"
  cp "$out/mission_run/summary.json" "$out/mission.json"
  # Speed: the same descent (seed 1, world from a warm cache) three times on one host thread and
  # three times with the frame rendered on a second one; host_s of each summary.json.
  cache="$out/world-cache"
  "$bin/trn_mission" --quiet --no-plots --duration 1 --world-cache "$cache" --out "$out/speed_warm" >/dev/null
  for threads in 1 2; do
    for i in 1 2 3; do
      echo "=== trn_mission speed, $threads host thread(s), run $i"
      flag=""; [ "$threads" = 1 ] && flag="--one-host-thread"
      "$bin/trn_mission" --quiet --no-plots --seed 1 $flag --world-cache "$cache" --out "$out/speed_${threads}_$i" >/dev/null
      cp "$out/speed_${threads}_$i/summary.json" "$out/speed_${threads}_$i.json"
    done
  done
  # Campaign throughput: 20 single-fault descents (every fifth run of single_late_100) on the
  # host's cores, wall time from start to report.
  if [ -x "$bin/trn_campaign" ]; then
    echo "=== trn_campaign throughput (20 runs of campaigns/single_late_100.toml)"
    rm -rf "$out/campaign_run"
    t0=$(python3 -c 'import time; print(time.time())')
    "$bin/trn_campaign" run campaigns/single_late_100.toml --shard 0/5 --mission "$bin/trn_mission" \
      --world-cache "$cache" --out "$out/campaign_run" --quiet
    t1=$(python3 -c 'import time; print(time.time())')
    runs=$(($(wc -l < "$out/campaign_run/runs.csv") - 1))
    printf '{"runs": %d, "wall_s": %s, "jobs": %d}\n' "$runs" "$(python3 -c "print($t1 - $t0)")" "$(nproc)" > "$out/campaign.json"
  fi
fi
python3 tools/build/bench_summary.py "$out"
echo "bench: results in $out/"
