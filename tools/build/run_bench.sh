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
fi
python3 tools/build/bench_summary.py "$out"
echo "bench: results in $out/"
