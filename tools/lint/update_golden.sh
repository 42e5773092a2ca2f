#!/usr/bin/env bash
# @file update_golden.sh
# @brief Rewrites the golden list of enabled clang-tidy checks after an intended change.
set -euo pipefail
cd "$(dirname "$0")/../.."
clang-tidy --list-checks kernel/x.cpp -- 2>/dev/null | sed -n 's/^ \+//p' | LC_ALL=C sort > tools/lint/clang_tidy_checks.golden
wc -l tools/lint/clang_tidy_checks.golden
