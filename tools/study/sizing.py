#!/usr/bin/env python3
"""@file sizing.py
@brief `make sizing`: how many vision tiles the descent needs, on the TILE64 and on Maestro.

Usage: tools/study/sizing.py BIN OUT [--chips tile64,maestro] [--landmarks 40,100,150,200]
                             [--rates 1,2] [--tiles 5,10,20,30,40] [--seeds 1,2,3] [--jobs 2]

Flies the whole default descent, no faults, for every chip x landmarks per frame
(`[vision] landmarks_per_frame`) x image rate (`[camera] rate_hz`) x vision tiles
(`--vision-tiles`, capped at the chip's: 35 on Maestro) x seed, JOBS runs at a time,
and writes into OUT:
  sizing.csv   one row per run (the figures of its summary.json)
  sizing.dat   one row per configuration: means and spreads over the seeds
  sizing.md    the tables per chip, and the fewest tiles that keep up with each load
  sizing.png   worst frame time and matches per frame against vision tiles, per chip and load (gnuplot)
Each run keeps its folder under OUT/runs/. A configuration "keeps up" when, on
every seed, every frame was processed (none left out while the coordinator was
busy, none left out by the vision supervisor's image rate), no work unit missed
the frame's deadline, the longest frame took no more than the frame period
(1 / rate), and the coordinator planned as many landmarks per frame as the
most any configuration of that load and seed planned (a tile takes one work unit of at
most 5 landmarks a frame, so fewer tiles plan fewer).
"""
import argparse
import os
import statistics
import sys

from flights import fly, fly_all, write_results

CHIP_TILES = {"tile64": 40, "maestro": 35}


def ints(text):
    return [int(x) for x in text.split(",") if x]


def run_one(binary, out, world, chip, lm, rate, tiles, seed):
    name = f"{chip}-lm{lm}-r{rate}-t{tiles}-s{seed}"
    folder = os.path.join(out, "runs", name)
    scenario = os.path.join(out, "scenarios", f"{chip}-lm{lm}-r{rate}.toml")
    s = fly([binary, "--quiet", "--no-plots", "--scenario", scenario, "--seed", str(seed), "--vision-tiles",
             str(tiles), "--world-cache", world, "--out", folder], folder, "sizing")
    return {
        "chip": chip, "landmarks": lm, "rate_hz": rate, "tiles": tiles, "seed": seed,
        "final_error_m": s["final_position_error_m"],
        "worst_frame_ms": s["worst_frame_ms"],
        "matches_per_frame": s["matches_per_frame_mean"],
        "planned_per_frame": s["vision_planned_per_frame"],
        "frames": s["frames"],
        "frames_seen": s["vision_frames_seen"],
        "frames_skipped": s["vision_frames_skipped"],
        "frames_rate_skipped": s["vision_frames_rate_skipped"],
        "units_lost": s["vision_units_lost"],
        "deadline_misses": s["deadline_misses"],
        "mission_lost": s["mission_lost"],
    }


def keeps_up(rows, rate, full_plan):
    """Every frame at the full rate, its whole plan dealt and answered in time, on every seed."""
    return all(r["frames_skipped"] == 0 and r["frames_rate_skipped"] == 0 and r["units_lost"] == 0 and
               r["worst_frame_ms"] <= 1000.0 / rate and
               r["planned_per_frame"] >= 0.99 * full_plan[(r["landmarks"], rate, r["seed"])] for r in rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("bin")
    ap.add_argument("out")
    ap.add_argument("--chips", default="tile64,maestro")
    ap.add_argument("--landmarks", default="40,100,150,200")
    ap.add_argument("--rates", default="1,2")
    ap.add_argument("--tiles", default="5,10,20,30,40")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    chips = [c for c in a.chips.split(",") if c]
    for c in chips:
        if c not in CHIP_TILES:
            sys.exit(f"sizing: no such chip {c} (allowed: {', '.join(CHIP_TILES)})")
    binary = os.path.join(a.bin, "trn_mission")
    world = os.path.join(a.out, "world")
    os.makedirs(os.path.join(a.out, "scenarios"), exist_ok=True)
    os.makedirs(world, exist_ok=True)
    landmarks, rates, seeds = ints(a.landmarks), ints(a.rates), ints(a.seeds)
    configs = []
    for chip in chips:
        tiles = sorted({min(t, CHIP_TILES[chip]) for t in ints(a.tiles)})
        for lm in landmarks:
            for rate in rates:
                with open(os.path.join(a.out, "scenarios", f"{chip}-lm{lm}-r{rate}.toml"), "w", encoding="utf-8") as f:
                    f.write(f'[scenario]\nname = "sizing"\nchip = "{chip}"\n[camera]\nrate_hz = {rate}\n'
                            f"[vision]\nlandmarks_per_frame = {lm}\n")
                for t in tiles:
                    configs.append((chip, lm, rate, t))
    jobs = [(binary, a.out, world, *c, s) for c in configs for s in seeds]
    rows = fly_all(jobs, run_one, a.jobs, "sizing")

    def group(chip, lm, rate, t):
        return [r for r in rows if (r["chip"], r["landmarks"], r["rate_hz"], r["tiles"]) == (chip, lm, rate, t)]

    full_plan = {}
    for r in rows:
        key = (r["landmarks"], r["rate_hz"], r["seed"])
        full_plan[key] = max(full_plan.get(key, 0.0), r["planned_per_frame"])
    dat = ["# chip landmarks rate_hz tiles worst_frame_ms_max matches_mean final_mean_m final_sd_m "
           "final_worst_m frames_skipped units_lost keeps_up period_ms"]
    md = []
    for chip in chips:
        tiles = sorted({c[3] for c in configs if c[0] == chip})
        md.append(f"\n### {chip}\n")
        md.append("Each cell: worst frame (ms) / matches per frame / final error mean +- sd (m) over "
                  f"{len(seeds)} seeds; `*` where frames were left out (busy, or the image rate halved) or work "
                  "units missed the deadline.\n")
        md.append("| landmarks | rate | " + " | ".join(f"{t} tiles" for t in tiles) + " | fewest tiles that keep up |")
        md.append("|---|---|" + "---|" * len(tiles) + "---|")
        for lm in landmarks:
            for rate in rates:
                cells = []
                fewest = None
                for t in tiles:
                    g = group(chip, lm, rate, t)
                    worst = max(r["worst_frame_ms"] for r in g)
                    matches = statistics.mean(r["matches_per_frame"] for r in g)
                    errs = [r["final_error_m"] for r in g]
                    sd = statistics.stdev(errs) if len(errs) > 1 else 0.0
                    skipped = sum(r["frames_skipped"] + r["frames_rate_skipped"] for r in g)
                    lost = sum(r["units_lost"] for r in g)
                    ok = keeps_up(g, rate, full_plan)
                    if ok and fewest is None:
                        fewest = t
                    mark = "" if skipped == 0 and lost == 0 else "*"
                    cells.append(f"{worst:.0f}{mark} / {matches:.0f} / {statistics.mean(errs):.2f} +- {sd:.2f}")
                    dat.append(f"{chip} {lm} {rate} {t} {worst:.1f} {matches:.1f} {statistics.mean(errs):.4f} "
                               f"{sd:.4f} {max(errs):.4f} {skipped} {lost} {1 if ok else 0} {1000.0 / rate:.0f}")
                md.append(f"| {lm} | {rate} Hz | " + " | ".join(cells) +
                          f" | {fewest if fewest is not None else 'none of these'} |")
    write_results(a.out, "sizing", rows, dat, md, plot(chips, landmarks, rates))


def plot(chips, landmarks, rates):
    """The gnuplot script of sizing.png."""
    frame, matches = [], []
    for chip in chips:
        for lm in landmarks:
            for rate in rates:
                sel = f'(strcol(1) eq "{chip}" && $2 == {lm} && $3 == {rate} ?'
                style = f"with linespoints dt {1 if chip == 'tile64' else 2}"
                title = f"title '{chip} {lm} lm {rate} Hz'"
                frame.append(f"'sizing.dat' using 4:{sel} $5 : 1/0) {style} {title}")
                if rate == rates[0]:
                    matches.append(f"'sizing.dat' using 4:{sel} $6 : 1/0) {style} title '{chip} {lm} lm'")
    frame += ["1000 with lines dt 3 lc rgb 'black' title '1 Hz frame period'",
              "500 with lines dt 3 lc rgb 'gray' title '2 Hz frame period'"]
    return ("set terminal pngcairo size 1100,1000 noenhanced\nset output 'sizing.png'\n"
            "set multiplot layout 2,1\nset grid\nset key outside right\nset xrange [0:42]\n"
            "set xlabel 'vision tiles the coordinator uses'\n"
            "set title 'Worst frame against vision tiles (default descent, no faults; solid TILE64, dashed Maestro)'\n"
            "set ylabel 'worst frame (ms)'\nset yrange [0:1100]\n"
            "plot " + ", \\\n     ".join(frame) + "\n"
            "set title 'Matches per frame against vision tiles (the same at 1 and 2 Hz)'\n"
            "set ylabel 'matches per frame'\nset yrange [0:*]\n"
            "plot " + ", \\\n     ".join(matches) + "\nunset multiplot\n")


if __name__ == "__main__":
    try:
        main()
    except RuntimeError as e:
        sys.exit(str(e))
