#!/usr/bin/env python3
"""Runs the guidance experiment (experiments/eyebot_guidance.xml) for seeds
1-10 and writes its results table into docs/eyebot.md, between the markers
<!-- eyebot_guidance results: begin --> and <!-- eyebot_guidance results: end -->.

    tools/eyebot_guidance_results.py [BUILD_DIR]     (default: build)

Each run is `colony run experiments/eyebot_guidance.xml --seed S`; the figures
are the last row of its metrics.csv (loop_functions/eyebot_guidance)."""
import os
import statistics
import sys
import tempfile

import docblock
import runs

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
DOC = os.path.join(ROOT, "docs", "eyebot.md")
SEEDS = range(1, 11)


def run(seed, out):
    return runs.last_metrics(BUILD, "experiments/eyebot_guidance.xml", seed, out)


def summary(name, values):
    if not values:
        return "%s: none." % name
    return "%s: median %.1f s, %.1f to %.1f s." % (name, statistics.median(values), min(values), max(values))


def main():
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in SEEDS:
            rows.append((seed, run(seed, os.path.join(tmp, str(seed)))))
    lines = ["",
             "| seed | target marked at (s) | 5 foot-bots there at (s) | foot-bots there at the end |",
             "|---|---|---|---|"]
    marks, reaches = [], []
    for seed, r in rows:
        mark, reach = float(r["mark_time"]), float(r["reach_time"])
        if mark >= 0:
            marks.append(mark)
        if reach >= 0:
            reaches.append(reach)
        lines.append("| %d | %s | %s | %d |" % (seed, "%.1f" % mark if mark >= 0 else "**never**",
                                               "%.1f" % reach if reach >= 0 else "**not in 300 s**",
                                               int(float(r["reached"]))))
    lines += ["",
              "%d of %d seeds succeed (5 foot-bots within 0.6 m of the target within 300 s). %s %s" % (
                  len(reaches), len(rows), summary("Marked", marks), summary("Reached", reaches)),
              "",
              "Written by `tools/eyebot_guidance_results.py` from runs of this tree; rerun it when the "
              "eye-bot, its devices, the engines or the controllers change.", ""]
    docblock.replace_block(DOC, "eyebot_guidance results", lines)
    print("docs/eyebot.md: results of %d seeds written" % len(rows))


if __name__ == "__main__":
    main()
