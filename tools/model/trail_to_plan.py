#!/usr/bin/env python3
"""Turns a counterexample of the TMR model (tools/model/tmr.pml) into a fault plan the mission image flies.

    trail_to_plan.py TRAIL [--name NAME] [--t0 S] [--phase S] [--late S] [--midjob S]

TRAIL is the guided replay of a SPIN trail, `spin -t [the run's -D options] tmr.pml` (tools/model/check.sh
writes it as trail.txt), or its whole `spin -t -p` print: only the model's own lines are read,

    MODEL fault round=R kind=K replica=P      (K: the F_* number of tmr.pml; P: 255 for the voter)
    MODEL event command_taken round=R code=C  (C: 1 filter_tmr, 2 filter_simplex)

and the plan (docs/FAULT_PLANS.md) goes to standard output.

Time: the model's round r is the filter's job J0 + r - 1, where J0 is the job that takes the first
filter_tmr (round 1). A telecommand sent at (J - 1) x 10 ms is taken by job J (the I/O tile forwards it
in the IMU stream: `command_taken` at job 501 for one sent at 5.0 s), so a command the model takes at
round r is sent at t0 + (r - 1) x 10 ms, t0 = --t0 (default 5.0). A fault at the start of round r is
injected --phase (default 0.5 ms) into job J's 10 ms, before the filter's tiles run it (they are
released 1.04 ms into their period in the image of this writing); a reset of the voter after its job
(kind 10) --late into it (default 1.1 ms: after the job's end, in the same release); a reset between a
delivery and the write of the voter's place (kind 8) --midjob into it (default 1.0219 ms: the last
instant before the place is written in the image of this writing; a window under a microsecond). What
the model chooses freely, the plan cannot: how long a hung tile stays hung (its watchdog decides in the
flight) and the order of the tiles in a release.
"""
import argparse
import re
import sys

# tmr.pml's F_* numbers: (kind, role, extra keys)
KINDS = {
    1: ("core_hang", "filter", {}),
    2: ("core_reset", "filter", {}),
    3: ("core_hang", "filter_replica", {}),
    4: ("core_reset", "filter_replica", {}),
    # the solution as sent fails the CRC its replica took (docs/FAULT_PLANS.md, nav_output)
    5: ("sdc", "filter_replica", {"point": '"nav_output"', "bit": "70"}),
    # a small change of the state (bit 40 of the position's first double): it passes the replica's checks
    6: ("sdc", "filter_replica", {"point": '"filter_state"', "bit": "40"}),
    # the position doubled (bit 116: the exponent of its second double): the replica's checks refuse it
    7: ("sdc", "filter_replica", {"point": '"filter_state"', "bit": "116"}),
    8: ("core_reset", "filter", {}),
    # a reset right after the replica's output: approximated by a reset in its release
    9: ("core_reset", "filter_replica", {}),
    10: ("core_reset", "filter", {}),
}
COMMANDS = {1: "filter_tmr", 2: "filter_simplex"}
FAULT_RE = re.compile(r"MODEL fault round=(\d+) kind=(\d+) replica=(\d+)")
CMD_RE = re.compile(r"MODEL event command_taken round=(\d+) code=(\d+)")


def parse(lines):
    """The faults (round, kind, replica) and the commands (round, code) of a trail, in order."""
    faults, commands = [], []
    for line in lines:
        m = FAULT_RE.search(line)
        if m:
            faults.append(tuple(int(g) for g in m.groups()))
            continue
        m = CMD_RE.search(line)
        if m:
            commands.append(tuple(int(g) for g in m.groups()))
    # spin -t -p prints a printf's text twice (the statement and its output): keep each event once
    return list(dict.fromkeys(faults)), list(dict.fromkeys(commands))


def job_start(t0, rnd):
    """The start of the 10 ms period of the job that the model's round rnd stands for, s."""
    return t0 + rnd * 0.010


def plan(lines, name, t0=5.0, phase=0.0005, late=0.0011, midjob=0.0010219):
    faults, commands = parse(lines)
    if not commands or commands[0][1] != 1:
        raise ValueError("the trail has no filter_tmr taken first (is it a trail of tmr.pml?)")
    first = commands[0][0]
    out = [f'# A counterexample of the TMR model (tools/model/tmr.pml), as a fault plan: model round r is',
           f'# the filter\'s job {int(round(t0 * 100)) + 1} + r - {first} (tools/model/trail_to_plan.py).',
           f'name = "{name}"', ""]
    for rnd, code in commands:
        if code not in COMMANDS:
            raise ValueError(f"unknown command code {code} at round {rnd}")
        out += ["[[command]]", f"t_s = {t0 + (rnd - first) * 0.010:.6f}", f'name = "{COMMANDS[code]}"', ""]
    for rnd, kind, replica in faults:
        if kind not in KINDS:
            raise ValueError(f"unknown fault kind {kind} at round {rnd}")
        what, role, extra = KINDS[kind]
        offset = late if kind == 10 else midjob if kind == 8 else phase
        out += ["[[fault]]", f"t_s = {job_start(t0, rnd - first + 1) + offset:.7f}", f'kind = "{what}"',
                f'role = "{role}"']
        if role == "filter_replica":
            if replica > 2:
                raise ValueError(f"fault kind {kind} at round {rnd} names no replica")
            out.append(f"instance = {replica}")
        out += [f"{k} = {v}" for k, v in extra.items()]
        out.append("")
    return "\n".join(out)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("trail")
    ap.add_argument("--name", default="model-trail")
    ap.add_argument("--t0", type=float, default=5.0, help="time of the first filter_tmr, s")
    ap.add_argument("--phase", type=float, default=0.0005, help="offset of a fault into its job's period, s")
    ap.add_argument("--late", type=float, default=0.0011, help="offset of a reset after the voter's job, s")
    ap.add_argument("--midjob", type=float, default=0.0010219, help="offset of a reset inside the voter's job, s")
    a = ap.parse_args(argv)
    with open(a.trail, encoding="utf-8") as f:
        lines = f.readlines()
    try:
        sys.stdout.write(plan(lines, a.name, a.t0, a.phase, a.late, a.midjob))
    except ValueError as e:
        print(f"trail_to_plan: {a.trail}: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
