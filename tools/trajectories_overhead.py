#!/usr/bin/env python3
"""Measures what recording trajectories costs: runs `colony run` on a scene
with trajectories off, CSV, CSV gzip, HDF5 and HDF5 deflate, interleaved,
REPEAT times each, and writes the table of medians into docs/data-output.md
and docs/benchmarks.md (between <!-- trajectories overhead: begin/end -->).

    tools/trajectories_overhead.py [--scene experiments/benchmarks/diffusion_10000.xml]
                                   [--every 10] [--threads 2] [--repeat 5] [--build build]

The time outside the steps is summary.json's wall_seconds - step_seconds:
loading, then the writing after each recorded tick (the steps are timed
alone). Every run must end with the same state hash: recording must not
change the simulation."""
import argparse
import datetime
import json
import os
import statistics
import subprocess
import tempfile

import docblock

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIGS = [  # label, --set overrides, file written
    ("off", [], None),
    ("CSV", ["output.format=csv"], "trajectories.csv"),
    ("CSV, gzip", ["output.format=csv", "output.compress=gzip"], "trajectories.csv.gz"),
    ("HDF5", ["output.format=hdf5"], "trajectories.h5"),
    ("HDF5, deflate", ["output.format=hdf5", "output.compress=gzip"], "trajectories.h5"),
]


def run(a, overrides, every, out):
    cmd = [os.path.join(ROOT, a.build, "bin", "colony"), "run", a.scene, "--quiet", "--threads",
           str(a.threads), "--out", out, "--overwrite"]
    if every:
        cmd += ["--set", "output.trajectories_every=%d" % every]
    for o in overrides:
        cmd += ["--set", o]
    subprocess.run(cmd, cwd=ROOT, check=True)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--scene", default="experiments/benchmarks/diffusion_10000.xml")
    p.add_argument("--every", type=int, default=10)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--build", default="build")
    a = p.parse_args()
    outside = {c[0]: [] for c in CONFIGS}
    steps = {c[0]: [] for c in CONFIGS}
    sizes, hashes, loads = {}, set(), []
    summary = None
    with tempfile.TemporaryDirectory(prefix="colony_traj_") as tmp:
        for _ in range(a.repeat):
            for label, overrides, name in CONFIGS:
                loads.append(os.getloadavg()[0])
                out = os.path.join(tmp, label.replace(", ", "_"))
                summary = run(a, overrides, a.every if name else 0, out)
                outside[label].append(summary["wall_seconds"] - summary["step_seconds"])
                steps[label].append(summary["step_seconds"])
                hashes.add(summary["final_state_hash"])
                if name:
                    sizes[label] = os.path.getsize(os.path.join(out, name))
    if len(hashes) != 1:
        raise SystemExit("the runs ended in different states: %s" % sorted(hashes))
    ticks, robots = summary["ticks"], summary["robots"]
    records = ticks // a.every + 1
    base_outside = statistics.median(outside["off"])
    base_steps = statistics.median(steps["off"])
    lines = ["",
             "| trajectories (%d ticks: %d records, %s rows) | file | outside the steps (s) | "
             "added per record | per robot | added to the %.2f s of steps |" % (
                 ticks, records, format(records * robots, ","), base_steps),
             "|---|---|---|---|---|---|",
             "| off | | %.2f (loading) | | | |" % base_outside]
    for label, _, _ in CONFIGS[1:]:
        added = statistics.median(outside[label]) - base_outside
        lines.append("| %s | %.1f MB | %.2f | %.1f ms | %.2f µs | %+.0f%% |" % (
            label, sizes[label] / 1e6, statistics.median(outside[label]), 1e3 * added / records,
            1e6 * added / records / robots, 100 * added / base_steps))
    lines += ["",
              "%s robots, trajectories every %d ticks, %d threads; medians of %d interleaved runs "
              "of each, measured %s with a load average of %.1f to %.1f; the state hash was the same "
              "in all %d runs. Written by `tools/trajectories_overhead.py --scene %s --every %d "
              "--threads %d --repeat %d`." % (
                  format(robots, ","), a.every, a.threads, a.repeat,
                  datetime.date.today().isoformat(), min(loads), max(loads),
                  a.repeat * len(CONFIGS), a.scene, a.every, a.threads, a.repeat), ""]
    for doc in ("data-output.md", "benchmarks.md"):
        docblock.replace_block(os.path.join(ROOT, "docs", doc), "trajectories overhead", lines)
    print("docs/data-output.md, docs/benchmarks.md: trajectories overhead written")


if __name__ == "__main__":
    main()
