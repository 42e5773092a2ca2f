#!/usr/bin/env bash
# @file size_report.sh
# @brief `make size`: link-time region sections, then per-tile used/free bytes after boot.
set -euo pipefail
image=$1
echo "== link-time sections of $image"
size -A "$image" | awk '$1 ~ /^\.(tile_ram|ddr|bss|data|text|rodata)$/ {printf "  %-10s %12d bytes\n", $1, $2}'
echo "== regions after boot (used / free / size per tile and DDR)"
"$image" --memory-map
