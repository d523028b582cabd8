#!/usr/bin/python3
"""Draws the Push-Pull results beside the seed's figure 6.6 from a sweep of
experiments/sweeps/pushpull-footbots.xml:

    colony sweep experiments/sweeps/pushpull-footbots.xml --out sweeps/pushpull --jobs 2
    /usr/bin/python3 tools/pushpull_figures.py sweeps/pushpull

writes docs/pushpull_fig6_6.png (three panels: completion time of each run,
success rate, mean completion time of the successful runs, against the number
of foot-bots) and the table between the markers
<!-- pushpull results: begin --> and <!-- pushpull results: end --> in
docs/pushpull.md. Needs Debian's python3-matplotlib (run it with
/usr/bin/python3)."""
import csv
import os
import statistics
import sys

import docblock

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "pushpull.md")
PNG = os.path.join(ROOT, "docs", "pushpull_fig6_6.png")
THRESHOLD = 50000  # ticks: the seed's failure threshold
COUNT = "arena.distribute.entity.quantity"


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: tools/pushpull_figures.py SWEEP_FOLDER")
    folder = sys.argv[1]
    with open(os.path.join(folder, "results.csv")) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{folder}/results.csv has no runs")
    by_count = {}
    for r in rows:
        by_count.setdefault(int(r[COUNT]), []).append(r)
    counts = sorted(by_count)
    table = []
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    xs, ys = [], []
    rates, means, wall = [], [], []
    for n in counts:
        runs = by_count[n]
        ok = [r for r in runs if r["status"] == "ok" and float(r["success"]) == 1]
        ticks = [float(r["completion_tick"]) for r in ok]
        xs += [n] * len(ticks)
        ys += ticks
        rate = len(ok) / len(runs)
        rates.append(100 * rate)
        means.append(statistics.mean(ticks) if ticks else float("nan"))
        wall += [float(r["wall_seconds"]) for r in runs]
        per_m2 = n / 3.0
        table.append(
            "| %d | %.1f | %d | %d%% | %s | %s | %s |"
            % (n, per_m2, len(runs), round(100 * rate),
               "%.0f" % statistics.mean(ticks) if ticks else "-",
               "%.0f" % statistics.median(ticks) if ticks else "-",
               "%.1f" % statistics.mean(float(r["connections"]) for r in runs)))
    axes[0].scatter(xs, ys, s=12)
    axes[0].set_ylim(0, THRESHOLD)
    axes[0].set_title("(a) time to complete (successful runs)")
    axes[0].set_ylabel("ticks (10 per second)")
    axes[1].bar(counts, rates)
    axes[1].set_ylim(0, 100)
    axes[1].set_title("(b) success rate")
    axes[1].set_ylabel("%% of %d seeds" % len(by_count[counts[0]]))
    axes[2].plot(counts, means, marker="o")
    axes[2].set_ylim(0, THRESHOLD)
    axes[2].set_title("(c) mean time of the successful runs")
    axes[2].set_ylabel("ticks")
    for ax in axes:
        ax.set_xlabel("foot-bots")
        ax.set_xticks(counts)
    fig.suptitle("Push-Pull in Colony: 2 hand-bots, 1-10 foot-bots, failure at %d ticks" % THRESHOLD)
    fig.tight_layout()
    fig.savefig(PNG, dpi=80)
    lines = ["",
             "| foot-bots | per m^2 of free floor | runs | success | mean ticks (successes) "
             "| median ticks | connections per run |",
             "|---|---|---|---|---|---|---|"] + table + [
        "",
        "%d runs; one run's wall time: median %.1f s, longest %.1f s (a failing run goes to %d ticks)."
        % (len(rows), statistics.median(wall), max(wall), THRESHOLD),
        "",
        "Written by `tools/pushpull_figures.py` from a sweep of "
        "`experiments/sweeps/pushpull-footbots.xml`; `docs/pushpull_fig6_6.png` is its figure.",
        ""]
    docblock.replace_block(DOC, "pushpull results", lines)
    print("wrote %s and the table in %s from %d runs" % (PNG, DOC, len(rows)))


if __name__ == "__main__":
    main()
