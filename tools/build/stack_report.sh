#!/usr/bin/env bash
# @file stack_report.sh
# @brief `make stack`: every flight function's frame (gcc -fstack-usage) against the budget.
#
# Usage: stack_report.sh OBJ_DIR SOURCE...  (STACK_FRAME_BUDGET bytes, default 4096)
# Fails on a frame over budget or on an unbounded dynamic frame (VLA, alloca).
set -uo pipefail
obj=$1; shift
budget=${STACK_FRAME_BUDGET:-4096}
files=()
for s in "$@"; do f="$obj/${s%.cpp}.su"; [ -f "$f" ] && files+=("$f"); done
if [ ${#files[@]} -eq 0 ]; then echo "stack: no .su files (build first)"; exit 1; fi
all=$(cat "${files[@]}" | awk -F'\t' '{print $2"\t"$3"\t"$1}' | sort -t$'\t' -k1,1nr)
echo "stack: ${#files[@]} flight objects, $(echo "$all" | wc -l) functions, frame budget $budget bytes"
echo "largest frames:"
echo "$all" | head -12 | awk -F'\t' '{printf "  %8d  %-16s %s\n", $1, $2, $3}'
over=$(echo "$all" | awk -F'\t' -v b="$budget" '$1 > b || $2 == "dynamic"')
if [ -n "$over" ]; then
  echo "stack: FAILED, over budget or unbounded:"; echo "$over" | sed 's/^/  /'; exit 1
fi
echo "stack: all frames within budget"
