#!/usr/bin/env python3
"""Runs the shelf-climbing experiment (experiments/handbot_shelf.xml) for seeds
1-10 and writes its results table into docs/handbot.md, between the markers
<!-- handbot_shelf results: begin --> and <!-- handbot_shelf results: end -->.

    tools/handbot_shelf_results.py [BUILD_DIR]     (default: build)

Each run is `colony run experiments/handbot_shelf.xml --seed S`; the figures are
the last row of its metrics.csv (loop_functions/handbot_shelf)."""
import os
import statistics
import sys

import docblock
import runs
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
DOC = os.path.join(ROOT, "docs", "handbot.md")
SEEDS = range(1, 11)


def run(seed, out):
    return runs.last_metrics(BUILD, "experiments/handbot_shelf.xml", seed, out)


def main():
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in SEEDS:
            r = run(seed, os.path.join(tmp, str(seed)))
            rows.append((seed, r))
    lines = ["",
             "| seed | success | time (s) | climbed (m) | grips on the board | book brought down | book still in a gripper |",
             "|---|---|---|---|---|---|---|"]
    times = []
    for seed, r in rows:
        ok = float(r["success"]) == 1
        t = float(r["success_time"])
        if ok:
            times.append(t)
        lines.append("| %d | %s | %s | %.2f | %d | %s | %s |" % (
            seed, "yes" if ok else "**no**", "%.1f" % t if ok else "-", float(r["climb_height"]),
            int(float(r["grips"])), "yes" if float(r["book_retrieved"]) == 1 else "no",
            "yes" if float(r["book_held"]) == 1 else "no"))
    lines.append("")
    if times:
        lines.append("%d of %d seeds succeed; time to success: median %.1f s, %.1f to %.1f s." % (
            len(times), len(rows), statistics.median(times), min(times), max(times)))
    else:
        lines.append("No seed succeeds.")
    lines += ["", "Written by `tools/handbot_shelf_results.py` from runs of this tree; rerun it when the "
              "hand-bot, its devices or the controller change.", ""]
    docblock.replace_block(DOC, "handbot_shelf results", lines)
    print("docs/handbot.md: results of %d seeds written" % len(rows))


if __name__ == "__main__":
    main()
