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
  "$b" --benchmark_out="$out/$name.json" --benchmark_out_format=json
done
# Whole-run figure: the mission image over the whole descent, default scenario,
# no faults; its summary.json (real-time factor, errors) is the result.
if [ -x "$bin/trn_mission" ]; then
  echo "=== trn_mission (whole descent)"
  "$bin/trn_mission" --quiet --out "$out/mission_run"
  cp "$out/mission_run/summary.json" "$out/mission.json"
  python3 - "$out/mission.json" <<'PY' || true
import json, sys
s = json.load(open(sys.argv[1]))
print("mission: %.1f emulated s in %.2f host s: real-time factor %.1f; final position error %.2f m" %
      (s["emulated_s"], s["host_s"], s["realtime_factor"], s["final_position_error_m"]))
PY
fi
echo "bench: results in $out/"
