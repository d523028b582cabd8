#!/usr/bin/python3
"""Draws the single-robot barrier results beside seed 004's figure 5.1 from a
sweep of experiments/sweeps/pockets-occlusion.xml:

    colony sweep experiments/sweeps/pockets-occlusion.xml --out sweeps/pockets-occlusion --jobs 2
    /usr/bin/python3 tools/pockets_figures.py sweeps/pockets-occlusion

writes docs/pockets_fig5_1.png (the four criteria of seed 004, 4.2, against the
occlusion threshold, each run a point, with the seed's real-robot medians as
lines) and the table between the markers <!-- pockets results: begin --> and
<!-- pockets results: end --> in docs/pockets.md. Needs Debian's
python3-matplotlib (run it with /usr/bin/python3)."""
import csv
import os
import statistics
import sys

import docblock

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "pockets.md")
PNG = os.path.join(ROOT, "docs", "pockets_fig5_1.png")
THRESHOLD = "loop_functions.params.occlusion_threshold"
QUOTA = 30
# (column, label, scale to the unit shown, seed 004's real-robot median (4.3))
CRITERIA = [("uniformity_deviation", "uniformity deviation u_d", 1, 0.13),
            ("integrity_deviation", "integrity deviation i_d (cm)", 100, 2.44),
            ("maximum_gap", "maximum gap d_m (cm)", 100, 10.48),
            ("construction_time", "construction time t_c (s)", 1, 2486)]


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: tools/pockets_figures.py SWEEP_FOLDER")
    folder = sys.argv[1]
    with open(os.path.join(folder, "results.csv")) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{folder}/results.csv has no runs")
    by = {}
    for r in rows:
        by.setdefault(float(r[THRESHOLD]), []).append(r)
    thresholds = sorted(by)
    fig, axes = plt.subplots(1, 4, figsize=(16, 4))
    lines = ["",
             "| occlusion threshold | runs | all 30 deposited | u_d | i_d (cm) | d_m (cm) | t_c (s) | wall time per run (s) |",
             "|---|---|---|---|---|---|---|---|"]
    for t in thresholds:
        runs = by[t]
        done = [r for r in runs if r["status"] == "ok" and float(r["deposited"]) >= QUOTA]
        meds = []
        for col, _, scale, _ in CRITERIA:
            values = [scale * float(r[col]) for r in done]
            meds.append(statistics.median(values) if values else float("nan"))
        wall = statistics.median(float(r["wall_seconds"]) for r in runs)
        lines.append("| %g%% | %d | %d | %.3f | %.2f | %.2f | %.0f | %.2f |" % (
            t, len(runs), len(done), meds[0], meds[1], meds[2], meds[3], wall))
    lines.append("| seed 004, real robot (20 trials) | 20 | 20 | 0.13 | 2.44 | 10.48 | 2486 | |")
    for ax, (col, label, scale, real) in zip(axes, CRITERIA):
        data = []
        for t in thresholds:
            data.append([scale * float(r[col]) for r in by[t]
                         if r["status"] == "ok" and float(r["deposited"]) >= QUOTA])
        ax.boxplot(data, labels=["%g%%" % t for t in thresholds])
        ax.axhline(real, color="red", linestyle="--", label="seed 004, real robot (median)")
        ax.set_xlabel("occlusion threshold")
        ax.set_title(label, fontsize=10)
    axes[0].legend(fontsize=8)
    fig.suptitle("One robot, 30 pockets, %d seeds per threshold (runs that deposited all 30); "
                 "seed 004 figure 5.1 shows the same criteria" % len(by[thresholds[0]]), fontsize=10)
    fig.tight_layout()
    fig.savefig(PNG, dpi=90)
    lines += ["",
              "Medians over the runs that deposited all 30 pockets. Written by `tools/pockets_figures.py` "
              "from a sweep of `experiments/sweeps/pockets-occlusion.xml` run on this tree; rerun both when the "
              "pockets, the manipulator or the controller change.", ""]
    docblock.replace_block(DOC, "pockets results", lines)
    print("docs/pockets.md and docs/pockets_fig5_1.png written from %d runs" % len(rows))


if __name__ == "__main__":
    main()
