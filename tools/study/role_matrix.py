#!/usr/bin/env python3
"""
@file role_matrix.py
@brief What each role's failure does, per role and fault kind, from a campaign's run folders.

Usage: tools/study/role_matrix.py CAMPAIGN_FOLDER   (a `trn_campaign run` output folder)

Reads each run's result.json (its kind, role and outcome), the one row of its faults.csv
(the join's verdict: diagnosis, detection latency, recovery, the event that recovered it,
the service gap) and its events.log (role_moved, supervisor_moved: the spare that took the role over), and
prints a Markdown table with one row per role and kind: runs, detected with the right
diagnosis (also when it was accused wrongly as well), misdiagnosed, the detection latency (median and max), recovered, the recovering
events, the service gap (median and max), who took over (the tile itself after its reset,
or a spare: "no move" when it recovered without one), and the outcomes that are not no_effect or detected_recovered. The flight's
own events decide all of it (the join, docs/FDIR.md); this only counts.
"""
import csv
import glob
import json
import os
import re
import statistics
import sys
from collections import Counter, defaultdict

KIND_ORDER = ["core_hang", "core_reset", "switch_fail", "link_fail", "seu"]
ROLE_ORDER = ["trn_supervisor", "vision_coordinator", "io", "filter", "filter_replica", "vision"]
MOVED = re.compile(r"role_moved: role slot \d+ moves from retired tile (\d+) to spare (\d+)")
REPLACED = re.compile(r"role_moved: worker slot \d+: tile (\d+) switched off for wrong results, spare (\d+)")
# The supervisor's watcher gives its role to the standby (fdir/health_agent.hpp).
SUPERVISOR = re.compile(r"supervisor_moved: the supervisor's tile (\d+) stayed silent .* standby (\d+) takes")


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def spread(values):
    """'median (max)' of the numbers given, '-' without any."""
    if not values:
        return "-"
    return f"{statistics.median(values):.0f} ({max(values):.0f})"


def read_run(folder):
    result_path = os.path.join(folder, "result.json")
    faults_path = os.path.join(folder, "out", "faults.csv")
    if not os.path.exists(result_path) or not os.path.exists(faults_path):
        return None
    with open(result_path, encoding="utf-8") as f:
        result = json.load(f)
    with open(faults_path, encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    if len(rows) != 1:
        return None  # one fault per run: the table is about that fault
    moved = []
    events = os.path.join(folder, "out", "events.log")
    if os.path.exists(events):
        with open(events, encoding="utf-8") as f:
            for line in f:
                m = MOVED.search(line) or REPLACED.search(line) or SUPERVISOR.search(line)
                if m:
                    moved.append(m.group(2))
    return result, rows[0], moved


def main():
    if len(sys.argv) != 2 or not os.path.isdir(os.path.join(sys.argv[1], "runs")):
        sys.stderr.write("usage: role_matrix.py CAMPAIGN_FOLDER (a trn_campaign run output folder with runs/)\n")
        return 2
    cells = defaultdict(list)
    for folder in sorted(glob.glob(os.path.join(sys.argv[1], "runs", "*"))):
        run = read_run(folder)
        if run is None:
            continue
        result, _, _ = run
        cells[(result.get("role", ""), result.get("kind", ""))].append(run)
    if not cells:
        sys.stderr.write("role_matrix.py: no run with one fault and its faults.csv under runs/\n")
        return 1
    print("| role | kind | runs | detected, right | misdiagnosed | latency ms, median (max) | recovered | "
          "recovered by | service gap ms, median (max) | taken over by | other outcomes |")
    print("|---|---|---:|---:|---:|---:|---:|---|---:|---|---|")
    roles = [r for r in ROLE_ORDER if any(k[0] == r for k in cells)] + sorted({k[0] for k in cells} - set(ROLE_ORDER))
    kinds = [k for k in KIND_ORDER if any(c[1] == k for c in cells)] + sorted({c[1] for c in cells} - set(KIND_ORDER))
    for role in roles:
        for kind in kinds:
            runs = cells.get((role, kind))
            if not runs:
                continue
            named = ("right", "right_and_wrong")  # right_and_wrong: named right, and wrongly as well
            right = sum(1 for _, f, _ in runs if f["diagnosis"] in named)
            wrong = sum(1 for r, _, _ in runs if r.get("misdiagnosed"))
            latency = [v for _, f, _ in runs if f["diagnosis"] in named for v in [number(f["latency_ms"])] if v is not None]
            recovered = sum(1 for _, f, _ in runs if f["recovery"] == "recovered")
            by = Counter(f["recovery_by"] for _, f, _ in runs if f["recovery"] == "recovered" and f["recovery_by"])
            gap = [v for _, f, _ in runs for v in [number(f["service_gap_ms"])] if v is not None]
            spares = Counter(s for _, _, moved in runs for s in moved)
            in_place = sum(1 for _, f, moved in runs if f["recovery"] == "recovered" and not moved)
            taken = []
            if in_place:
                taken.append(f"no move {in_place}x")
            taken += [f"spare {t} {n}x" for t, n in sorted(spares.items(), key=lambda kv: -kv[1])]
            others = Counter(r["outcome"] for r, _, _ in runs if r["outcome"] not in ("no_effect", "detected_recovered"))
            no_effect = sum(1 for r, _, _ in runs if r["outcome"] == "no_effect")
            other = ", ".join(f"{k} {v}" for k, v in sorted(others.items()))
            if no_effect:
                other = (other + ", " if other else "") + f"no_effect {no_effect}"
            print(f"| {role} | {kind} | {len(runs)} | {right} | {wrong} | {spread(latency)} | {recovered} | "
                  f"{', '.join(f'{k} {v}' for k, v in by.most_common(3)) or '-'} | {spread(gap)} | "
                  f"{', '.join(taken) or '-'} | {other or '-'} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
