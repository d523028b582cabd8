#!/usr/bin/env python3
"""Runs colony_bench on benchmark scenes at given thread counts and writes the
table of its medians into docs/benchmarks.md, between the markers
<!-- NAME results: begin --> and <!-- NAME results: end -->.

    tools/benchmark_table.py NAME SCENE.xml [SCENE.xml ...] [--threads 1,2] [--repeat 3] [--build build]
                             [--ticks T] [--set PATH=VALUE ...] [--against BUILD]

e.g. tools/benchmark_table.py mixed_11000 experiments/benchmarks/mixed_11000.xml experiments/benchmarks/diffusion_10000.xml
Each row is one scene at one thread count: colony_bench's RESULT line (medians
of the repetitions), with the load average when it ran.

With --against BUILD (another build folder, e.g. an earlier commit's), each row
compares the two builds instead: their runs alternate (one run of BUILD, one of
--build, --repeat times), so that a shared machine's slow minutes fall on both,
and the medians of each stand side by side."""
import argparse
import datetime
import os
import shlex
import statistics
import subprocess
import sys

import docblock

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "benchmarks.md")


def bench(build, scene, threads, repeat, sets=(), ticks=None):
    exe = os.path.join(ROOT, build, "bin", "colony_bench")
    extra = [arg for s in sets for arg in ("--set", s)] + (["--ticks", str(ticks)] if ticks else [])
    out = subprocess.run([exe, scene, "--threads", str(threads), "--repeat", str(repeat)] + extra, cwd=ROOT,
                         check=True, capture_output=True, text=True).stdout
    line = [l for l in out.splitlines() if l.startswith("RESULT ")][-1]
    return dict(kv.split("=", 1) for kv in line.split()[1:])


def main():
    p = argparse.ArgumentParser()
    p.add_argument("name")
    p.add_argument("scenes", nargs="+")
    p.add_argument("--threads", default="1,2")
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--build", default="build")
    p.add_argument("--ticks", type=int, help="ticks per run (default: the scene's length)")
    p.add_argument("--set", action="append", default=[], metavar="PATH=VALUE",
                   help="an override passed to colony_bench for every scene (repeatable)")
    p.add_argument("--against", metavar="BUILD",
                   help="compare with this build folder, runs interleaved (the 'before' columns)")
    a = p.parse_args()
    if a.against:
        write_table(a, ["| scene | threads | robot-steps/s before | after | change "
                        "| CPU ns per robot-step before | after | state hash before | after |",
                        "|---|---|---|---|---|---|---|---|---|"], compared_row,
                    "Medians of %d interleaved pairs of runs" % a.repeat if a.repeat > 1 else "One pair of runs")
    else:
        write_table(a, ["| scene | threads | robot-steps/s | CPU ns per robot-step | bytes per robot (peak) | load "
                        "| physics share | state hash |",
                        "|---|---|---|---|---|---|---|---|"], row,
                    "Medians of %d repetitions" % a.repeat if a.repeat > 1 else "One run of each")


def row(a, scene, t):
    r = bench(a.build, scene, t, a.repeat, a.set, a.ticks)
    return "| %s | %d | %s | %s | %s | %s s | %s%% | `%s` |" % (
        r["scene"], t, format(int(float(r["steps_per_s_median"])), ","), r["cpu_ns_per_robot_step"],
        format(int(r["bytes_per_robot"]), ","), r["load_s_median"], r["physics_pct"], r["state_hash"])


def compared_row(a, scene, t):
    runs = {"before": [], "after": []}
    for _ in range(a.repeat):
        runs["before"].append(bench(a.against, scene, t, 1, a.set, a.ticks))
        runs["after"].append(bench(a.build, scene, t, 1, a.set, a.ticks))
    sps = {k: statistics.median(float(r["steps_per_s_median"]) for r in v) for k, v in runs.items()}
    ns = {k: statistics.median(float(r["cpu_ns_per_robot_step"]) for r in v) for k, v in runs.items()}
    hashes = {k: " ".join("`%s`" % h for h in sorted({r["state_hash"] for r in v})) for k, v in runs.items()}
    return "| %s | %d | %s | %s | %+.1f%% | %.0f | %.0f | %s | %s |" % (
        runs["after"][0]["scene"], t, format(int(sps["before"]), ","), format(int(sps["after"]), ","),
        100.0 * (sps["after"] / sps["before"] - 1), ns["before"], ns["after"], hashes["before"],
        "same" if hashes["after"] == hashes["before"] else hashes["after"])


def write_table(a, header, make_row, what):
    """One row per scene and thread count (make_row(a, scene, threads)), then a line saying what the
    figures are (`what`), when and how they were made, into the block NAME of docs/benchmarks.md."""
    lines = [""] + header
    loads = []
    for scene in a.scenes:
        for t in [int(x) for x in a.threads.split(",")]:
            loads.append(os.getloadavg()[0])
            lines.append(make_row(a, scene, t))
    lines += ["",
              "%s%s, measured %s with a load average of %.1f to %.1f before the runs; "
              "written by `tools/benchmark_table.py %s`." % (
                  what, ", %d ticks each" % a.ticks if a.ticks else "", datetime.date.today().isoformat(),
                  min(loads), max(loads), shlex.join(sys.argv[1:])), ""]
    docblock.replace_block(DOC, "%s results" % a.name, lines)
    print("docs/benchmarks.md: %s written" % a.name)


if __name__ == "__main__":
    main()
