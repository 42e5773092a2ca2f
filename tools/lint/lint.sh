#!/usr/bin/env bash
# @file lint.sh
# @brief The static-analysis gates: flight rules, the docs' names (doc_refs.py), clang-tidy (golden check list), cppcheck.
#
# Usage: lint.sh BIN_DIR SOURCE...   (BIN_DIR holds flight_rules and compile_commands.json;
#        run from the repository root; SOURCE... are the files clang-tidy checks)
# Fails on the first gate with any finding; prints a count per gate.
set -uo pipefail
bin=$1; shift
srcs=("$@")
here=$(cd "$(dirname "$0")" && pwd)
status=0
jobs=$(nproc 2>/dev/null || echo 2)

# 1. Flight rules over the whole tree: per-file rules, the board's interface,
#    the layer order and the include graph (the checker lists the files itself).
if ! "$bin/flight_rules" --tree .; then
  echo "lint: flight rules FAILED"; status=1
fi

# 2. clang-tidy: first the check list must match the golden list.
if ! python3 "$here/doc_refs.py" .; then
  echo "lint: the docs name paths, make targets or options that do not exist (tools/lint/doc_refs.py)"; status=1
fi

golden="$here/clang_tidy_checks.golden"
actual=$(clang-tidy --list-checks kernel/x.cpp -- 2>/dev/null | sed -n 's/^ \+//p' | LC_ALL=C sort)
if ! diff -u "$golden" <(echo "$actual") >/dev/null; then
  echo "lint: the enabled clang-tidy checks differ from $golden:"
  diff -u "$golden" <(echo "$actual") | sed -n '3,$p' | grep '^[-+]' | head -40
  echo "lint: if the change is intended, update the golden list (tools/lint/update_golden.sh)"
  status=1
fi

# clang-tidy over the flight and tool sources, in parallel, all output kept.
log=$(mktemp); trap 'rm -f "$log"' EXIT
printf '%s\n' "${srcs[@]}" | xargs -P "$jobs" -n 4 clang-tidy -p "$bin" --quiet \
  --extra-arg=-Wno-unknown-warning-option --extra-arg=-Wno-unused-command-line-argument >"$log" 2>&1
tidy_rc=$?
findings=$(grep -cE '(warning|error):' "$log")
if [ "$tidy_rc" -ne 0 ] || [ "$findings" -ne 0 ]; then
  grep -E -A3 '(warning|error):' "$log" | head -120
  echo "lint: clang-tidy FAILED ($findings findings)"; status=1
else
  echo "lint: clang-tidy clean over ${#srcs[@]} files"
fi

# 3. cppcheck over the compilation database, restricted to our own sources.
db=$(mktemp -d); trap 'rm -rf "$log" "$db"' EXIT
{ echo "["; grep -E '"file":"(bsp_tile64|kernel|udn|fdir|trn|tools)/' "$bin/compile_commands.json" | sed '1s/^,//'; echo "]"; } > "$db/compile_commands.json"
if ! cppcheck --project="$db/compile_commands.json" --enable=warning,performance,portability \
     --error-exitcode=1 --inline-suppr --quiet -j "$jobs" --std=c++20 \
     --suppress=missingIncludeSystem --suppress='*:/usr/include/*' --config-exclude=/usr/include \
     --template='{file}:{line}: [{id}] {message}'; then
  echo "lint: cppcheck FAILED"; status=1
else
  echo "lint: cppcheck clean"
fi

[ "$status" -eq 0 ] && echo "lint: all gates passed"
exit "$status"
