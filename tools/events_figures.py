#!/usr/bin/python3
"""Runs seed 000's event experiments and writes their results into
docs/events.md:

    /usr/bin/python3 tools/events_figures.py BUILD_DIR [SWEEPS_DIR]

1. experiments/e4_latency.xml, 50 seeds for each controller mode (poll,
   events) and rate (67, 25, 10 Hz): the stopping distances, drawn as
   histograms in docs/events_latency.png and summed up in the table between
   <!-- e4 latency: begin --> and <!-- e4 latency: end -->;
2. experiments/e4_bandwidth.xml, 10 seeds of one minute for each mode and
   arena (open, walls, cluttered): the bus load, drawn in
   docs/events_bandwidth.png and tabled between <!-- e4 bandwidth: begin -->
   and <!-- e4 bandwidth: end -->, with the ratio polling / events.

The sweeps go to SWEEPS_DIR (default: colony_e4_sweeps in the system's
temporary folder) as e4_latency and e4_bandwidth, replacing what an earlier
run of this script left there.
Needs Debian's python3-matplotlib (run it with /usr/bin/python3)."""
import csv
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

import docblock

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "events.md")
LATENCY_PNG = os.path.join(ROOT, "docs", "events_latency.png")
BANDWIDTH_PNG = os.path.join(ROOT, "docs", "events_bandwidth.png")
MODE_WS, RATE_WS = "controllers.wall_stop[ws].params.mode", "controllers.wall_stop[ws].rate"
MODE_AV, ENV = "controllers.avoid[av].params.mode", "loop_functions.params.env"
RATES = ["67", "25", "10"]
ENVS = ["open", "walls", "cluttered"]


def sweep(build, out, experiment, params, seeds):
    shutil.rmtree(out, ignore_errors=True)
    env = dict(os.environ, COLONY_PLUGIN_PATH=os.path.join(build, "lib", "colony"))
    command = [os.path.join(build, "bin", "colony"), "sweep",
               os.path.join(ROOT, "experiments", experiment), "--seeds", seeds,
               "--out", out, "--jobs", "2", "--quiet"]
    for p in params:
        command += ["--param", p]
    subprocess.run(command, env=env, check=True)
    with open(os.path.join(out, "results.csv")) as f:
        rows = list(csv.DictReader(f))
    bad = [r["run"] for r in rows if r["status"] != "ok"]
    if bad:
        sys.exit("%s: runs not ok: %s" % (out, ", ".join(bad)))
    return rows


def latency(build, folder):
    rows = sweep(build, os.path.join(folder, "e4_latency"), "e4_latency.xml",
                 [MODE_WS + "=poll,events", RATE_WS + "=" + ",".join(RATES)], "1..50")
    mm = {}
    for r in rows:
        if float(r["stopped"]) != 1:
            sys.exit("run %s did not stop" % r["run"])
        mm.setdefault((r[MODE_WS], r[RATE_WS]), []).append(1000 * float(r["stop_distance"]))
    panels = [("events", "10", "event-based (controller steps at 10 Hz)")] + [
        ("poll", rate, "polling at %s Hz" % rate) for rate in RATES]
    lo = min(min(v) for v in mm.values())
    hi = max(max(v) for v in mm.values())
    bins = [lo - 0.25 + 0.5 * i for i in range(int((hi - lo) / 0.5) + 3)]
    fig, axes = plt.subplots(len(panels), 1, figsize=(7, 8), sharex=True)
    for ax, (mode, rate, title) in zip(axes, panels):
        ax.hist(mm[(mode, rate)], bins=bins, color="tab:blue" if mode == "events" else "tab:orange")
        ax.set_title(title, fontsize=10)
        ax.set_ylabel("runs")
    axes[-1].set_xlabel("distance to the wall when stopped d (mm)")
    fig.suptitle("Stopping distance, 50 runs each (Colony, experiments/e4_latency.xml)")
    fig.tight_layout()
    fig.savefig(LATENCY_PNG, dpi=80)
    lines = ["", "| control | controller rate | runs | mean d (mm) | std dev (mm) | min | max |",
             "|---|---|---|---|---|---|---|"]
    for mode in ["events", "poll"]:
        for rate in RATES:
            d = mm[(mode, rate)]
            lines.append("| %s | %s Hz | %d | %.2f | %.2f | %.2f | %.2f |"
                         % ("event-based" if mode == "events" else "polling", rate, len(d),
                            statistics.mean(d), statistics.stdev(d), min(d), max(d)))
    lines += ["", "Written by `tools/events_figures.py` from %d runs of "
              "`experiments/e4_latency.xml`; `docs/events_latency.png` is its figure." % len(rows),
              ""]
    docblock.replace_block(DOC, "e4 latency", lines)


def bandwidth(build, folder):
    rows = sweep(build, os.path.join(folder, "e4_bandwidth"), "e4_bandwidth.xml",
                 [ENV + "=" + ",".join(ENVS), MODE_AV + "=poll,events"], "1..10")
    load = {}
    for r in rows:
        load.setdefault((r[ENV], r[MODE_AV]), []).append(
            float(r["bus_bytes"]) / float(r["simulated_seconds"]))
    lines = ["", "| arena | runs | polling at 67 Hz (B/s) | events: median (B/s) | events: min .. max "
             "| polling / events: median | worst case (busiest run) |",
             "|---|---|---|---|---|---|---|"]
    for env in ENVS:
        poll, events = load[(env, "poll")], load[(env, "events")]
        lines.append("| %s | %d + %d | %.0f | %.1f | %.1f .. %.1f | %.0fx | %.0fx |"
                     % (env, len(poll), len(events), statistics.median(poll),
                        statistics.median(events), min(events), max(events),
                        statistics.median(poll) / statistics.median(events),
                        statistics.median(poll) / max(events)))
    lines += ["", "Written by `tools/events_figures.py` from %d one-minute runs of "
              "`experiments/e4_bandwidth.xml`; `docs/events_bandwidth.png` is its figure."
              % len(rows), ""]
    docblock.replace_block(DOC, "e4 bandwidth", lines)
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.boxplot([load[(env, "events")] for env in ENVS])
    ax.set_xticks(range(1, len(ENVS) + 1), ENVS)
    poll = statistics.median(load[(ENVS[0], "poll")])
    ax.axhline(poll, color="tab:orange", linestyle="--")
    ax.text(0.6, poll * 0.8, "polling at 67 Hz: %.0f B/s" % poll, color="tab:orange")
    ax.set_yscale("log")
    ax.set_ylabel("bus load (B/s), log scale")
    ax.set_title("Bus load of event-based obstacle avoidance, 10 one-minute runs per arena")
    fig.tight_layout()
    fig.savefig(BANDWIDTH_PNG, dpi=80)


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: tools/events_figures.py BUILD_DIR [SWEEPS_DIR]")
    build = os.path.abspath(sys.argv[1])
    folder = sys.argv[2] if len(sys.argv) == 3 else os.path.join(tempfile.gettempdir(), "colony_e4_sweeps")
    latency(build, folder)
    bandwidth(build, folder)
    print("wrote %s, %s and the tables in %s" % (LATENCY_PNG, BANDWIDTH_PNG, DOC))


if __name__ == "__main__":
    main()
