#!/usr/bin/python3
"""Runs the construction experiments (experiments/construction_bridge.xml,
construction_tower.xml, construction_remote.xml) for seeds 1-20 each and
writes the results table into docs/construction.md, between the markers
<!-- construction results: begin --> and <!-- construction results: end -->.

    /usr/bin/python3 tools/construction_table.py [BUILD_DIR] [--jobs N]   (default: build, 2)

Each run is `colony run experiments/construction_TASK.xml --seed S`; the
figures are the last row of its metrics.csv (loop_functions/construction_metrics):
success and outcome_time; a run that did not succeed is counted as
  fell into the ditch    failed = 1 (the robot's base 2 cm below the floor);
  cube half on / jammed  the time ran out with a cube more than 5 degrees off
                         level (cubes_tilted > 0): half on another cube, or
                         across the ditch's edge;
  timeout                the time ran out otherwise.
Grasps by a corner are counted apart, from the controller's own count in the
per-robot table (trajectories.csv, column failed_grasps: the magnet engaged on
a cube met by a corner or askew and did not hold it; the controller backs off
and tries again), over all runs of a task whatever their outcome, with the
IR approaches the controller gave up (lost_approaches: no cube came nearer).
A run whose last failure was such a grasp still ends as a timeout. Likewise
the bridge checks: repairs (attempts to mend a bridge cube the manipulator's
IR sensors saw sticking up out of the ditch) and unrepaired (the robot saw a
bridge cube still not flat and did not cross). And the looks at the tower that
did not find its top in the image (tower_unseen: the robot then stacked on
where it last thought the tower stood), and the cubes put on the tower that the
manipulator's IR sensors then saw not stacked straight (tower_misplaced: half
on, aside, or fallen off; counted, not mended). A run stops on success, so the
last cube's check is counted only in runs that did not succeed."""
import argparse
import os
import statistics
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

import docblock
import runs

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "construction.md")
SEEDS = range(1, 21)
# (task, file, the seed's success rate and mean time: seed 001, table 2)
TASKS = [
    ("bridge (2 local cubes)", "experiments/construction_bridge.xml", "95%", "100 s"),
    ("tower (3 local cubes)", "experiments/construction_tower.xml", "95%", "286 s"),
    ("bridge + tower, remote cubes", "experiments/construction_remote.xml", "80%", "726 s"),
]


def classify(r):
    if float(r["success"]) == 1:
        return "success"
    if float(r["failed"]) == 1:
        return "fell"
    if float(r.get("cubes_tilted", 0)) > 0:
        return "half_on"
    return "timeout"


def run(build, experiment, seed, out):
    """The last row of metrics.csv of `colony run EXPERIMENT --seed SEED`, with
    the controller's counts from the last row of its per-robot table."""
    r = runs.last_metrics(build, experiment, seed, out,
                          ["output.trajectories_every=100", "output.format=csv", "output.compress=none"])
    robot = runs.last_row(os.path.join(out, "trajectories.csv"))
    for name in ("failed_grasps", "lost_approaches", "repairs", "unrepaired", "tower_unseen",
                 "tower_misplaced"):
        r[name] = robot[name]
    return r


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default="build")
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        jobs = [(name, path, seed) for name, path, _, _ in TASKS for seed in SEEDS]

        def one(job):
            name, path, seed = job
            out = os.path.join(tmp, "%s_%d" % (os.path.basename(path), seed))
            return job, run(args.build, path, seed, out)

        with ThreadPoolExecutor(max_workers=args.jobs) as pool:
            for (name, path, seed), r in pool.map(one, jobs):
                results[(name, seed)] = r
    lines = ["",
             "| experiment | Colony: success | Colony: mean time (median, range) | seed 001: success | "
             "seed 001: mean time | Colony: fell into the ditch | cube half on / jammed | timeout | "
             "grasps by a corner (runs) | IR approaches given up (runs) | jammed bridge cube: repair "
             "attempts (runs) | bridge seen unfinished, not crossed | tower not found in the image (runs) | "
             "tower cube seen not stacked straight (runs) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    per_seed = []
    for name, path, seed_success, seed_time in TASKS:
        rows = [results[(name, s)] for s in SEEDS]
        kinds = [classify(r) for r in rows]
        times = [float(r["outcome_time"]) for r, k in zip(rows, kinds) if k == "success"]
        ok = len(times)
        if times:
            timing = "%.0f s (%.0f s, %.0f-%.0f s)" % (statistics.mean(times), statistics.median(times),
                                                      min(times), max(times))
        else:
            timing = "-"
        corner = [int(float(r["failed_grasps"])) for r in rows]
        lost = [int(float(r["lost_approaches"])) for r in rows]
        repairs = [int(float(r["repairs"])) for r in rows]
        unrepaired = [int(float(r["unrepaired"])) for r in rows]
        unseen = [int(float(r["tower_unseen"])) for r in rows]
        misplaced = [int(float(r["tower_misplaced"])) for r in rows]
        lines.append("| %s | %d / %d (%.0f%%) | %s | %s | %s | %d | %d | %d | %d (%d) | %d (%d) | %d (%d) | %d | %d (%d) | %d (%d) |" % (
            name, ok, len(rows), 100.0 * ok / len(rows), timing, seed_success, seed_time,
            kinds.count("fell"), kinds.count("half_on"), kinds.count("timeout"),
            sum(corner), sum(1 for c in corner if c), sum(lost), sum(1 for c in lost if c),
            sum(repairs), sum(1 for c in repairs if c), sum(1 for c in unrepaired if c),
            sum(unseen), sum(1 for c in unseen if c), sum(misplaced), sum(1 for c in misplaced if c)))
        per_seed.append("%s: %s." % (name, ", ".join(
            "%d %s" % (s, "%.0f s" % float(r["outcome_time"]) if k == "success" else k.replace("_", " "))
            for s, r, k in zip(SEEDS, rows, kinds))))
    lines += ["", "Per seed (1 to 20):", ""] + ["- " + p for p in per_seed]
    lines += ["", "Written by `/usr/bin/python3 tools/construction_table.py` from runs of this tree "
              "(seeds 1 to 20 of each file, as shipped); rerun it when the controller, the camera, the "
              "manipulator or dynamics3d change.", ""]
    docblock.replace_block(DOC, "construction results", lines)
    print("docs/construction.md: %d runs written" % len(results))


if __name__ == "__main__":
    sys.exit(main())
