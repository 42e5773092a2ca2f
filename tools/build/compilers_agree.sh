#!/usr/bin/env bash
# @file compilers_agree.sh
# @brief Flies the same short missions with the GCC image and the Clang image and fails unless every
#        pair of trace hashes is the same; on a difference, names the first differing event.
#
# Usage: compilers_agree.sh GCC_BIN_DIR CLANG_BIN_DIR OUT_DIR SECONDS SEED...
#   GCC_BIN_DIR holds trn_mission and trn_trace, CLANG_BIN_DIR trn_mission. Each flight is
#   trn_mission --duration SECONDS --seed SEED (the default scenario, no fault plan), then the first
#   seed with tests/fixtures/fault_plans/early_faults.toml, and the first seed for 12 s with
#   filter_tmr_and_back.toml (the filter goes TMR at 5 s and back at 10 s: the deepest task stacks),
#   then the first seed and the TMR flight again on Maestro (--chip maestro),
#   each with its trace dumped to OUT_DIR/<compiler>-<flight>.trace. Prints one line per flight.
set -uo pipefail
gcc_bin=$1; clang_bin=$2; out=$3; seconds=$4; shift 4
seeds=("$@")
rm -rf "$out"; mkdir -p "$out"
status=0
fly() {  # fly BIN NAME DURATION ARGS...
  local bin=$1 name=$2 duration=$3; shift 3
  if ! "$bin/trn_mission" --quiet --no-plots --duration "$duration" --out "$out/$name" \
       --trace-dump "$out/$name.trace" "$@" >"$out/$name.log" 2>&1; then
    echo "compilers-agree: $bin/trn_mission $* failed:"; tail -5 "$out/$name.log"; return 1
  fi
  sed -n 's/.*"trace_hash": *"\([0-9a-f]*\)".*/\1/p' "$out/$name/summary.json"
}
flights=()
# Each flight: seed, duration, fault plan (- for none), chip.
for s in "${seeds[@]}"; do flights+=("$s $seconds - tile64"); done
flights+=("${seeds[0]} $seconds early_faults tile64")
flights+=("${seeds[0]} 12 filter_tmr_and_back tile64")
flights+=("${seeds[0]} $seconds - maestro")
flights+=("${seeds[0]} 12 filter_tmr_and_back maestro")
for f in "${flights[@]}"; do
  read -r seed duration plan chip <<<"$f"
  args=(--seed "$seed" --chip "$chip")
  name="seed$seed"
  if [ "$plan" != "-" ]; then
    args+=(--faults "tests/fixtures/fault_plans/$plan.toml")
    name="$name-$plan"
  fi
  [ "$chip" = tile64 ] || name="$name-$chip"
  g=$(fly "$gcc_bin" "gcc-$name" "$duration" "${args[@]}") || { status=1; continue; }
  c=$(fly "$clang_bin" "clang-$name" "$duration" "${args[@]}") || { status=1; continue; }
  if [ -n "$g" ] && [ "$g" = "$c" ]; then
    printf 'compilers-agree: %-30s %3ss  gcc %s  clang %s  same\n' "$name" "$duration" "$g" "$c"
  else
    printf 'compilers-agree: %-30s %3ss  gcc %s  clang %s  DIFFERENT\n' "$name" "$duration" "$g" "$c"
    "$gcc_bin/trn_trace" --chip "$chip" diff "$out/gcc-$name.trace" "$out/clang-$name.trace"
    status=1
  fi
done
[ "$status" -eq 0 ] && echo "compilers-agree: GCC and Clang fly the same bits (${#flights[@]} flights)"
exit "$status"
