"""@file flights.py
@brief What the flight studies (sizing.py, bad_cores.py) share: flying trn_mission runs side by side,
       and writing a study's rows, table, data and plot.
"""
import concurrent.futures
import csv
import json
import os
import subprocess
import sys


def fly(cmd, folder, label):
    """Flies @p cmd into @p folder unless its summary.json is there already; @return the summary."""
    summary = os.path.join(folder, "summary.json")
    if not os.path.exists(summary):
        r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, check=False)
        if r.returncode != 0:
            raise RuntimeError(f"{label}: {' '.join(cmd)} failed ({r.returncode}): {r.stderr.strip()}")
    with open(summary, encoding="utf-8") as f:
        return json.load(f)


def fly_all(jobs, run_one, workers, label):
    """run_one(*job) for every job, @p workers at a time, in order. The first runs alone: it builds the
    world in the cache folder, which two runs must not write at once."""
    rows = [run_one(*jobs[0])]
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        futures = [pool.submit(run_one, *j) for j in jobs[1:]]
        for i, fut in enumerate(futures):
            rows.append(fut.result())
            if (i + 2) % 20 == 0:
                print(f"{label}: {i + 2} of {len(jobs)} runs flown", flush=True)
    return rows


def write_results(out, name, rows, dat, md, gnuplot):
    """OUT/NAME.csv (the rows), .dat, .md, .gp and the plot gnuplot draws from them."""
    with open(os.path.join(out, f"{name}.csv"), "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    for ext, lines in (("dat", dat), ("md", md)):
        with open(os.path.join(out, f"{name}.{ext}"), "w", encoding="utf-8") as f:
            f.write("\n".join(lines) + "\n")
    with open(os.path.join(out, f"{name}.gp"), "w", encoding="utf-8") as f:
        f.write(f"# Run in this folder: gnuplot {name}.gp\n" + gnuplot)
    r = subprocess.run(["gnuplot", f"{name}.gp"], cwd=out, stdin=subprocess.DEVNULL, check=False)
    if r.returncode != 0:
        print(f"{name}: gnuplot failed; the tables are in {out}/{name}.md", file=sys.stderr)
    print("\n".join(md))
    print(f"{name}: results in {out}/ ({name}.md, {name}.csv, {name}.dat, {name}.png)")
