#!/usr/bin/env bash
# @file compilers_agree.sh
# @brief Flies the same short missions with the GCC image and the Clang image and fails unless every
#        pair of trace hashes is the same; on a difference, names the first differing event.
#
# Usage: compilers_agree.sh GCC_BIN_DIR CLANG_BIN_DIR OUT_DIR SECONDS SEED...
#   GCC_BIN_DIR holds trn_mission and trn_trace, CLANG_BIN_DIR trn_mission. Each flight is
#   trn_mission --duration SECONDS --seed SEED (the default scenario, no fault plan, and the
#   fixture plan tests/fixtures/fault_plans/early_faults.toml for the first seed), with its
#   trace dumped to OUT_DIR/<compiler>-<flight>.trace. Prints one line per flight.
set -uo pipefail
gcc_bin=$1; clang_bin=$2; out=$3; seconds=$4; shift 4
seeds=("$@")
rm -rf "$out"; mkdir -p "$out"
status=0
fly() {  # fly BIN NAME ARGS...
  local bin=$1 name=$2; shift 2
  if ! "$bin/trn_mission" --quiet --no-plots --duration "$seconds" --out "$out/$name" \
       --trace-dump "$out/$name.trace" "$@" >"$out/$name.log" 2>&1; then
    echo "compilers-agree: $bin/trn_mission $* failed:"; tail -5 "$out/$name.log"; return 1
  fi
  sed -n 's/.*"trace_hash": *"\([0-9a-f]*\)".*/\1/p' "$out/$name/summary.json"
}
flights=()
for s in "${seeds[@]}"; do flights+=("seed $s"); done
flights+=("seed ${seeds[0]} faults")
for f in "${flights[@]}"; do
  read -r _ seed faults <<<"$f"
  args=(--seed "$seed")
  [ -n "$faults" ] && args+=(--faults tests/fixtures/fault_plans/early_faults.toml)
  name="seed$seed${faults:+-faults}"
  g=$(fly "$gcc_bin" "gcc-$name" "${args[@]}") || { status=1; continue; }
  c=$(fly "$clang_bin" "clang-$name" "${args[@]}") || { status=1; continue; }
  if [ -n "$g" ] && [ "$g" = "$c" ]; then
    printf 'compilers-agree: %-18s %ss  gcc %s  clang %s  same\n' "$name" "$seconds" "$g" "$c"
  else
    printf 'compilers-agree: %-18s %ss  gcc %s  clang %s  DIFFERENT\n' "$name" "$seconds" "$g" "$c"
    "$gcc_bin/trn_trace" diff "$out/gcc-$name.trace" "$out/clang-$name.trace"
    status=1
  fi
done
[ "$status" -eq 0 ] && echo "compilers-agree: GCC and Clang fly the same bits (${#flights[@]} flights)"
exit "$status"
