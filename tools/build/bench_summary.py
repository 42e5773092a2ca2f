#!/usr/bin/env python3
"""`make bench`'s closing summary: the vision and speed figures of one run, side by side.

Reads what run_bench.sh left in build/bench/: the Google Benchmark JSON of each
benchmark, the text ncc_bench printed (TILE64 cycles of the coarse correlation),
and the whole descent's summary.json. Prints one block; a figure whose source is
missing is printed as "not measured" (never made up).
"""
import json
import os
import sys

out = sys.argv[1] if len(sys.argv) > 1 else "build/bench"


def bench(name):
    """{benchmark name: entry} of build/bench/<name>.json, or {} when absent."""
    path = os.path.join(out, name + ".json")
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return {b["name"]: b for b in json.load(f).get("benchmarks", []) if b.get("run_type", "iteration") == "iteration"}


def cpu_us(b, name):
    e = b.get(name)
    if e is None:
        return None
    scale = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}[e.get("time_unit", "ns")]
    return e["cpu_time"] * scale


def fmt_ratio(a, b):
    return "%.2fx" % (a / b) if a and b else "n/a"


lines = []
ncc = bench("ncc_bench")
fh, fo = cpu_us(ncc, "BM_Fine_Hand"), cpu_us(ncc, "BM_Fine_OpenCV")
ch, ct, co = cpu_us(ncc, "BM_Coarse_Hand"), cpu_us(ncc, "BM_Coarse_Transform"), cpu_us(ncc, "BM_Coarse_OpenCV")
if fh and fo:
    lines.append("fine NCC 21 on 49 (host CPU): hand-coded %.0f us, OpenCV %.0f us: hand-coded takes %s OpenCV's time"
                 % (fh, fo, fmt_ratio(fh, fo)))
else:
    lines.append("fine NCC: not measured (ncc_bench did not run)")
if ch and ct and co:
    lines.append("coarse NCC 64 on 256 (host CPU): spatial %.1f ms, transform %.1f ms, OpenCV %.1f ms: "
                 "transform takes %s OpenCV's time, spatial %s" % (ch / 1e3, ct / 1e3, co / 1e3, fmt_ratio(ct, co),
                                                                  fmt_ratio(ch, co)))
else:
    lines.append("coarse NCC: not measured (ncc_bench did not run)")
txt = os.path.join(out, "ncc_bench.txt")
if os.path.exists(txt):
    with open(txt) as f:
        for line in f:
            if line.startswith("TILE64 cycles, coarse") or line.startswith("transform surface =="):
                lines.append(line.strip())

flt = bench("filter_bench")
for key, what in (("BM_FilterJobPropagateAnd15Lagged", "filter job, propagation + 15 lagged matches, tight"),
                  ("BM_FilterJobPropagateAnd15LaggedLoose", "the same job while the position is loose")):
    e = flt.get(key)
    lines.append("%s: %s" % (what, "%.2f ms of the 10 ms period (TILE64)" % e["tile64_ms"] if e else "not measured"))

def host_seconds(threads):
    """host_s of the speed runs with @p threads host threads (run_bench.sh), sorted; [] when absent."""
    found = []
    for i in (1, 2, 3):
        path = os.path.join(out, "speed_%d_%d.json" % (threads, i))
        if os.path.exists(path):
            with open(path) as f:
                s = json.load(f)
            found.append((s["host_s"], s["emulated_s"]))
    return sorted(found)


for threads, what in ((1, "one host thread"), (2, "the frame rendered on a second host thread")):
    runs = host_seconds(threads)
    if runs:
        best, med = runs[0], runs[len(runs) // 2]
        lines.append("descent speed, %s (seed 1, %d runs): best %.2f host s for %.0f s (real-time factor %.1f), "
                     "median %.2f s (%.1f)" % (what, len(runs), best[0], best[1], best[1] / best[0], med[0],
                                               med[1] / med[0]))
    else:
        lines.append("descent speed, %s: not measured" % what)
camp = os.path.join(out, "campaign.json")
if os.path.exists(camp):
    with open(camp) as f:
        c = json.load(f)
    lines.append("campaign throughput: %d single-fault descents in %.1f s wall on %d cores: %.0f runs per host hour"
                 % (c["runs"], c["wall_s"], c["jobs"], c["runs"] * 3600.0 / c["wall_s"]))
else:
    lines.append("campaign throughput: not measured")

mission = os.path.join(out, "mission.json")
if os.path.exists(mission):
    with open(mission) as f:
        s = json.load(f)
    lines.append("whole descent (seed %d, %.0f s): real-time factor %.1f; %d frames, %.1f matches per frame; "
                 "longest frame %.0f ms; %d deadline misses; final error %.2f m"
                 % (s["seed"], s["emulated_s"], s["realtime_factor"], s["frames"], s["matches_per_frame_mean"],
                    s.get("worst_frame_ms", float("nan")), s["deadline_misses"], s["final_position_error_m"]))
    if "vision_coordinator_ready_s" in s:
        lines.append("vision coordinator ready at %.3f s (landmark table %s); frames captured before it %d; fix at %.2f s"
                     % (s["vision_coordinator_ready_s"],
                        "from the ground" if s.get("landmarks_from_ground") == 1 else "selected on board",
                        s.get("vision_frames_before_ready", 0), s.get("fix_at_s", float("nan"))))
    if "coarse_stage_ms" in s:
        lines.append("coarse stage: %.1f ms emulated (warp and decimation, %d bands dealt to the vision tiles, "
                     "computed and gathered, the match); %d bands computed by the coordinator instead"
                     % (s["coarse_stage_ms"], s.get("coarse_bands_sent", 0), s.get("coarse_bands_redone", 0)))
    bands = [(k[len("matches_per_frame_alt_"):-2].replace("_", "-"), v, s.get("frames_alt_" + k[len("matches_per_frame_alt_"):], 0))
             for k, v in s.items() if k.startswith("matches_per_frame_alt_")]
    if bands:
        lines.append("matches per frame by altitude: " + ", ".join("%s m %.0f (%d frames)" % (b, v, n) for b, v, n in bands))
else:
    lines.append("whole descent: not measured (trn_mission did not run)")

print("=== summary (issue 21's figures)")
for line in lines:
    print("  " + line)
