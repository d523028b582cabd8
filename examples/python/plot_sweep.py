#!/usr/bin/env python3
"""Plots a sweep (a `colony sweep --out` folder), notebook style: the final value of a metric
against a swept parameter (mean and standard deviation over seeds, one line per value of a second
parameter if there is one), and the metric's mean over time. Writes a PNG (matplotlib, Agg: no
display needed).

    colony sweep experiments/diffusion.xml --out sweeps/speed --seeds 1..4 \\
        --param controllers.diffusion[dc].params.velocity=0.02,0.05,0.1,0.2 \\
        --param arena.distribute.entity.quantity=30,120
    PYTHONPATH=build/python /usr/bin/python3 examples/python/plot_sweep.py sweeps/speed \\
        --metric mean_displacement --out speed.png"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from colony import results  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("sweep", help="a `colony sweep --out` folder")
    p.add_argument("--metric", default="mean_displacement",
                   help="a metric of the loop functions (a column of results.csv)")
    p.add_argument("--x", help="the parameter on the x axis (default: the first swept one)")
    p.add_argument("--out", default="sweep.png", help="the PNG to write")
    a = p.parse_args()

    sweep = results.load_sweep(a.sweep)
    r = sweep.results
    if a.metric not in r.columns:
        p.error(f"no metric {a.metric!r} in {a.sweep}/results.csv; its columns: "
                + ", ".join(r.columns))
    varying = [c for c in sweep.params if r[c].nunique() > 1]
    x = a.x or (varying[0] if varying else None)
    if x is None or x not in sweep.params:
        p.error(f"--x must be one of the swept parameters: {', '.join(sweep.params)}")
    others = [c for c in varying if c != x]
    group = others[0] if others else None
    ok = r[r["status"] == "ok"]
    if ok.empty:
        raise SystemExit(f"{a.sweep}: no run ended well (status ok); nothing to plot")

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    # Final values: mean +- standard deviation over the seeds.
    for key, rows in (ok.groupby(group) if group else [(None, ok)]):
        stats = rows.groupby(x)[a.metric].agg(["mean", "std"]).reset_index()
        label = f"{short(group)} = {key}" if group else None
        left.errorbar(stats[x], stats["mean"], yerr=stats["std"].fillna(0), marker="o",
                      capsize=3, label=label)
    left.set_xlabel(short(x))
    left.set_ylabel(f"{a.metric} at the end")
    left.set_title(f"{len(ok)} runs, {ok['seed'].nunique()} seeds each")
    if group:
        left.legend()
    # Over time: the mean over seeds, one line per value of x.
    ts = sweep.timeseries
    ts = ts[(ts["metric"] == a.metric) & ts["run"].isin(ok["run"])]
    for key, rows in ts.groupby(x):
        mean = rows.groupby("time")["value"].mean()
        right.plot(mean.index, mean.values, label=f"{short(x)} = {key}")
    right.set_xlabel("time (s)")
    right.set_ylabel(a.metric)
    right.set_title("mean over runs" + (f" (and over {short(group)})" if group else ""))
    right.legend(fontsize="small")
    fig.suptitle(a.sweep)
    fig.tight_layout()
    fig.savefig(a.out, dpi=100)
    print(f"{a.out}: {a.metric} against {x} over {len(ok)} runs")
    return 0


def short(path):
    """The last part of a parameter's path ("velocity" for controllers.diffusion[dc].params.velocity)."""
    return path.rsplit(".", 1)[-1] if path else path


if __name__ == "__main__":
    sys.exit(main())
