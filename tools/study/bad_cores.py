#!/usr/bin/env python3
"""@file bad_cores.py
@brief `make bad-cores`: navigation as vision cores go bad, with the spares on and off, on both chips.

Usage: tools/study/bad_cores.py BIN OUT [--chips tile64,maestro] [--kinds hang,shift]
                                [--bad 0,1,2,5,10,20] [--spares on,off] [--seeds 1,2,3]
                                [--landmarks N] [--rate HZ] [--jobs 2]

Flies the whole default descent with k vision tiles gone bad from 6 s on, spread
over the chip's vision tiles (instance i * count / k), for every chip x kind x k
x spares x seed, JOBS runs at a time:
  hang   the tile hangs four times, a second apart: its watchdog resets it three
         times, then the tile-health supervisor gives it up for good;
  shift  every match the tile makes from then on is 2 px off in u (a lasting sdc
         at match_position): the coordinator's check finds it, it is reset, and
         it is replaced by a spare while it stays wrong.
With `--spares off` the tile-health supervisor has no spare (trn_mission
--no-spares): a tile given up is not replaced. The load is `--landmarks` per
frame at `--rate` Hz (default 200 at 1 Hz: a tile takes at most 5 landmarks a
frame, so with 200 every healthy tile's 5 matches count; docs/PERFORMANCE.md,
"How many vision tiles"). Writes into OUT:
  bad_cores.csv  one row per run;  bad_cores.dat / bad_cores.md  means over the seeds;
  bad_cores.png  final error and matches per frame against k (gnuplot).
"""
import argparse
import os
import statistics
import sys

from flights import fly, fly_all, write_results

VISION_TILES = {"tile64": 40, "maestro": 35}
START_S = 6.0


def ints(text):
    return [int(x) for x in text.split(",") if x]


def plan_text(kind, k, count):
    out = [f'name = "bad_cores_{kind}_{k}"']
    for i in range(k):
        inst = i * count // k
        if kind == "hang":
            for n in range(4):
                out.append(f'\n[[fault]]\nt_s = {START_S + n:.1f}\nkind = "core_hang"\nrole = "vision"\ninstance = {inst}')
        else:
            out.append(f'\n[[fault]]\nt_s = {START_S:.1f}\nkind = "sdc"\nrole = "vision"\ninstance = {inst}\n'
                       'point = "match_position"\nshift = 2.0')
    return "\n".join(out) + "\n"


def run_one(binary, out, chip, kind, k, spares, seed):
    name = f"{chip}-{kind}-k{k}-spares_{spares}-s{seed}"
    folder = os.path.join(out, "runs", name)
    cmd = [binary, "--quiet", "--no-plots", "--scenario", os.path.join(out, "scenarios", f"{chip}.toml"),
           "--seed", str(seed), "--world-cache", os.path.join(out, "world"), "--out", folder]
    if k > 0:
        cmd += ["--faults", os.path.join(out, "plans", f"{chip}-{kind}-{k}.toml")]
    if spares == "off":
        cmd.append("--no-spares")
    s = fly(cmd, folder, "bad_cores")
    return {
        "chip": chip, "kind": kind, "bad": k, "spares": spares, "seed": seed,
        "final_error_m": s["final_position_error_m"],
        "matches_per_frame": s["matches_per_frame_mean"],
        "frames": s["frames"],
        "healthy_tiles_at_end": s["vision_healthy_tiles"],
        "rate_div_at_end": s["vision_rate_div"],
        "tiles_replaced": s["vision_tiles_replaced"],
        "faults_injected": s["faults_injected"],
        "faults_detected": s["faults_detected"],
        "misdiagnosed": s.get("faults_misdiagnosed", 0),
        "false_alarms": s["false_alarms"],
        "mission_lost": s["mission_lost"],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("bin")
    ap.add_argument("out")
    ap.add_argument("--chips", default="tile64,maestro")
    ap.add_argument("--kinds", default="hang,shift")
    ap.add_argument("--bad", default="0,1,2,5,10,20")
    ap.add_argument("--spares", default="on,off")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--landmarks", type=int, default=200)
    ap.add_argument("--rate", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    chips = [c for c in a.chips.split(",") if c]
    kinds = [k for k in a.kinds.split(",") if k]
    spares_set = [s for s in a.spares.split(",") if s]
    for c in chips:
        if c not in VISION_TILES:
            sys.exit(f"bad_cores: no such chip {c} (allowed: {', '.join(VISION_TILES)})")
    for k in kinds:
        if k not in ("hang", "shift"):
            sys.exit(f"bad_cores: no such kind {k} (allowed: hang, shift)")
    for s in spares_set:
        if s not in ("on", "off"):
            sys.exit(f"bad_cores: --spares takes on and off, not {s}")
    bad, seeds = ints(a.bad), ints(a.seeds)
    for sub in ("scenarios", "plans", "world", "runs"):
        os.makedirs(os.path.join(a.out, sub), exist_ok=True)
    for chip in chips:
        with open(os.path.join(a.out, "scenarios", f"{chip}.toml"), "w", encoding="utf-8") as f:
            f.write(f'[scenario]\nname = "bad_cores"\nchip = "{chip}"\n[camera]\nrate_hz = {a.rate}\n'
                    f"[vision]\nlandmarks_per_frame = {a.landmarks}\n")
        for kind in kinds:
            for k in bad:
                if k > VISION_TILES[chip]:
                    sys.exit(f"bad_cores: {k} bad tiles of {VISION_TILES[chip]} on the {chip}")
                with open(os.path.join(a.out, "plans", f"{chip}-{kind}-{k}.toml"), "w", encoding="utf-8") as f:
                    f.write(plan_text(kind, k, VISION_TILES[chip]))
    binary = os.path.join(a.bin, "trn_mission")
    jobs = [(binary, a.out, chip, kind, k, sp, seed) for chip in chips for kind in kinds for k in bad
            for sp in spares_set for seed in seeds]
    rows = fly_all(jobs, run_one, a.jobs, "bad_cores")
    dat = ["# chip kind spares bad final_mean_m final_sd_m final_worst_m matches_mean healthy_mean replaced_mean "
           "halved_runs lost_runs runs"]
    md = [f"Load: {a.landmarks} landmarks per frame at {a.rate} Hz; means over seeds {a.seeds}.\n",
          "| chip | kind | spares | bad tiles | final error mean +- sd (worst), m | matches per frame | "
          "healthy vision tiles at the end | tiles replaced | runs at half rate | runs lost |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for chip in chips:
        for kind in kinds:
            for sp in spares_set:
                for k in bad:
                    g = [r for r in rows if (r["chip"], r["kind"], r["spares"], r["bad"]) == (chip, kind, sp, k)]
                    errs = [r["final_error_m"] for r in g]
                    sd = statistics.stdev(errs) if len(errs) > 1 else 0.0
                    matches = statistics.mean(r["matches_per_frame"] for r in g)
                    healthy = statistics.mean(r["healthy_tiles_at_end"] for r in g)
                    replaced = statistics.mean(r["tiles_replaced"] for r in g)
                    halved = sum(1 for r in g if r["rate_div_at_end"] > 1)
                    lost = sum(int(r["mission_lost"]) for r in g)
                    dat.append(f"{chip} {kind} {sp} {k} {statistics.mean(errs):.4f} {sd:.4f} {max(errs):.4f} "
                               f"{matches:.1f} {healthy:.1f} {replaced:.1f} {halved} {lost} {len(g)}")
                    md.append(f"| {chip} | {kind} | {sp} | {k} | {statistics.mean(errs):.2f} +- {sd:.2f} "
                              f"({max(errs):.2f}) | {matches:.0f} | {healthy:.1f} | {replaced:.1f} | {halved} of "
                              f"{len(g)} | {lost} |")
    write_results(a.out, "bad_cores", rows, dat, md, plot(chips, kinds, spares_set))


def plot(chips, kinds, spares_set):
    """The gnuplot script of bad_cores.png."""
    err, mat = [], []
    for chip in chips:
        for kind in kinds:
            for sp in spares_set:
                sel = f'(strcol(1) eq "{chip}" && strcol(2) eq "{kind}" && strcol(3) eq "{sp}" ?'
                title = f"{chip} {kind} spares {sp}"
                err.append(f"'bad_cores.dat' using 4:{sel} $5 : 1/0) with linespoints title '{title}'")
                mat.append(f"'bad_cores.dat' using 4:{sel} $8 : 1/0) with linespoints title '{title}'")
    return ("set terminal pngcairo size 1100,900 noenhanced\nset output 'bad_cores.png'\n"
            "set multiplot layout 2,1\nset grid\nset key outside right\nset xlabel 'vision tiles gone bad'\n"
            "set title 'Final position error, mean over seeds'\nset ylabel 'm'\n"
            "plot " + ", \\\n     ".join(err) + "\n"
            "set title 'Matches per frame, mean over seeds'\nset ylabel 'matches'\n"
            "plot " + ", \\\n     ".join(mat) + "\nunset multiplot\n")


if __name__ == "__main__":
    try:
        main()
    except RuntimeError as e:
        sys.exit(str(e))
