#!/usr/bin/python3
"""Draws the barrier results beside seed 004's figures from sweeps of
experiments/sweeps/pockets-occlusion.xml (one robot) and
experiments/sweeps/pockets-scalability.xml (1-8 robots):

    colony sweep experiments/sweeps/pockets-occlusion.xml --out sweeps/pockets-occlusion --jobs 2
    colony sweep experiments/sweeps/pockets-scalability.xml --out sweeps/pockets-scalability --jobs 2
    /usr/bin/python3 tools/pockets_figures.py sweeps/pockets-occlusion sweeps/pockets-scalability

From the first: docs/pockets_fig5_1.png (the four criteria of seed 004, 4.2,
against the occlusion threshold, with the seed's real-robot medians as lines)
and the table between <!-- pockets results: begin --> and <!-- pockets
results: end --> in docs/pockets.md. From the second (optional):
docs/pockets_fig5_3.png (the criteria against the swarm size, mean and
standard deviation, as the seed's figure 5.3), docs/pockets_fig5_4-6.png (the
average iteration time against the ideal xi_c(1)/m, the normalised times and
the efficiency against the swarm density, as figures 5.4-5.6) and the table
between <!-- pockets swarm: begin --> and <!-- pockets swarm: end -->. Needs
Debian's python3-matplotlib (run it with /usr/bin/python3)."""
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
PNG_SWARM = os.path.join(ROOT, "docs", "pockets_fig5_3.png")
PNG_EFFICIENCY = os.path.join(ROOT, "docs", "pockets_fig5_4-6.png")
ROBOTS = "arena.distribute.entity.quantity"
SWARM_QUOTA = 112
THRESHOLD = "loop_functions.params.occlusion_threshold"
QUOTA = 30
# (column, label, scale to the unit shown, seed 004's real-robot median (4.3))
CRITERIA = [("uniformity_deviation", "uniformity deviation u_d", 1, 0.13),
            ("integrity_deviation", "integrity deviation i_d (cm)", 100, 2.44),
            ("maximum_gap", "maximum gap d_m (cm)", 100, 10.48),
            ("construction_time", "construction time t_c (s)", 1, 2486)]


def read_rows(folder):
    with open(os.path.join(folder, "results.csv")) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{folder}/results.csv has no runs")
    return rows


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: tools/pockets_figures.py OCCLUSION_SWEEP_FOLDER [SCALABILITY_SWEEP_FOLDER]")
    single(sys.argv[1])
    if len(sys.argv) == 3:
        swarm(sys.argv[2])


def mean_sd(values):
    return (statistics.mean(values), statistics.pstdev(values)) if values else (float("nan"), float("nan"))


def swarm(folder):
    rows = read_rows(folder)
    by = {}
    for r in rows:
        by.setdefault(int(r[ROBOTS]), []).append(r)
    sizes = sorted(by)
    if 1 not in by:
        sys.exit(f"{folder}: no one-robot runs, so no xi_c(1) for the efficiency")

    def complete(runs):
        return [r for r in runs if r["status"] == "ok" and r["deposited"] and float(r["deposited"]) >= SWARM_QUOTA]

    done = {m: complete(by[m]) for m in sizes}
    xi = {m: mean_sd([float(r["average_iteration_time"]) for r in done[m]]) for m in sizes}
    xi1 = xi[1][0]
    density = {m: statistics.mean(float(r["swarm_density"]) for r in by[m]) for m in sizes}
    lines = ["",
             "| robots | runs | all 112 deposited | u_d | i_d (cm) | d_m (cm) | xi_c(m) (s) | xi_d(m) = xi_c(1)/m (s) "
             "| swarm density rho_s | efficiency eta_s | wall time per run (s) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    crit = {}
    for m in sizes:
        ud = mean_sd([float(r["uniformity_deviation"]) for r in done[m]])
        idv = mean_sd([100 * float(r["integrity_deviation"]) for r in done[m]])
        dm = mean_sd([100 * float(r["maximum_gap"]) for r in done[m]])
        crit[m] = (ud, idv, dm, xi[m])
        wall = statistics.median(float(r["wall_seconds"]) for r in by[m])
        lines.append("| %d | %d | %d | %.3f +- %.3f | %.2f +- %.2f | %.1f +- %.1f | %.1f +- %.1f | %.1f | %.4f | %.2f | %.2f |" % (
            m, len(by[m]), len(done[m]), ud[0], ud[1], idv[0], idv[1], dm[0], dm[1], xi[m][0], xi[m][1],
            xi1 / m, density[m], xi1 / (m * xi[m][0]), wall))
    lines += ["",
              "Means +- standard deviations over the runs that deposited all 112 pockets, as the seed's figure 5.3 "
              "shows them; xi_c(1) is the one-robot runs' mean and eta_s = xi_d(m) / xi_c(m) (eq. 5.1-5.4). "
              "Written by `tools/pockets_figures.py` from a sweep of `experiments/sweeps/pockets-scalability.xml` "
              "run on this tree.", ""]
    docblock.replace_block(DOC, "pockets swarm", lines)

    fig, axes = plt.subplots(1, 4, figsize=(16, 4))
    titles = ["uniformity deviation u_d", "integrity deviation i_d (cm)", "maximum gap d_m (cm)",
              "average iteration time xi_c (s)"]
    for k, (ax, title) in enumerate(zip(axes, titles)):
        ax.errorbar(sizes, [crit[m][k][0] for m in sizes], yerr=[crit[m][k][1] for m in sizes],
                    marker="o", capsize=3)
        ax.set_xlabel("robots")
        ax.set_title(title, fontsize=10)
        ax.set_xticks(sizes)
    fig.suptitle("Swarms of 1-8 robots, 112 pockets, %d seeds each: mean and standard deviation "
                 "(seed 004 figure 5.3 shows the same)" % len(by[sizes[0]]), fontsize=10)
    fig.tight_layout()
    fig.savefig(PNG_SWARM, dpi=90)

    fig, axes = plt.subplots(1, 3, figsize=(15, 4))
    ax = axes[0]
    ax.plot(sizes, [xi[m][0] for m in sizes], "o-", label="actual xi_c(m)")
    ax.plot(sizes, [xi1 / m for m in sizes], "s--", label="ideal xi_d(m) = xi_c(1)/m")
    ax.set_xlabel("robots m")
    ax.set_ylabel("average iteration time (s)")
    ax.set_title("as seed 004 figure 5.4", fontsize=10)
    ax.legend(fontsize=8)
    rho = [density[m] for m in sizes]
    ax = axes[1]
    ax.plot(rho, [xi[m][0] / xi1 for m in sizes], "o-", label="actual")
    ax.plot(rho, [1 / m for m in sizes], "s--", label="ideal 1/m")
    ax.set_xlabel("swarm density rho_s")
    ax.set_ylabel("normalised average iteration time")
    ax.set_title("as seed 004 figure 5.5", fontsize=10)
    ax.legend(fontsize=8)
    ax = axes[2]
    ax.plot(rho, [xi1 / (m * xi[m][0]) for m in sizes], "o-", label="Colony")
    ax.axhline(0.95, color="red", linestyle="--", label="seed 004: above 0.95")
    ax.set_ylim(0, 1.1)
    ax.set_xlabel("swarm density rho_s")
    ax.set_ylabel("efficiency eta_s")
    ax.set_title("as seed 004 figure 5.6", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(PNG_EFFICIENCY, dpi=90)
    print("docs/pockets.md, docs/pockets_fig5_3.png and docs/pockets_fig5_4-6.png written from %d runs" % len(rows))


def single(folder):
    rows = read_rows(folder)
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
