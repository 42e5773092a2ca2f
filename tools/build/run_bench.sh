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
echo "bench: results in $out/"
