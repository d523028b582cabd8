#!/usr/bin/env python3
"""Measures what serving a run to the live viewer costs the simulation:
colony_serve on a scene plainly (no server), served with nobody connected,
and served to one client (colony_viewer_probe: a WebSocket client that
receives every frame and draws nothing), interleaved, REPEAT times each.
Writes the table of medians into docs/viewer.md and docs/benchmarks.md
(between <!-- viewer overhead: begin --> and <!-- viewer overhead: end -->).

    tools/viewer_overhead.py [--scene experiments/benchmarks/diffusion_10000.xml]
                             [--seconds 30] [--threads 1] [--repeat 5] [--build build]

colony_serve times the ticks after the first (served, the run waits for a
client before its first tick) and prints robot-steps/s."""
import argparse
import datetime
import os
import re
import socket
import statistics
import subprocess

import docblock

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PLAIN, NOBODY, CLIENT = "plain", "served, nobody connected", "served, one client"


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def steps_per_second(output):
    m = re.search(r"([0-9.e+]+) robot-steps/s", output)
    if not m:
        raise SystemExit("colony_serve printed no robot-steps/s:\n" + output)
    return float(m.group(1))


def run(a, case):
    """robot-steps/s, and the client's frames per second (None without one)."""
    serve = os.path.join(ROOT, a.build, "bin", "colony_serve")
    probe = os.path.join(ROOT, a.build, "bin", "colony_viewer_probe")
    base = [serve, a.scene, "--set", "framework.experiment.length=%g" % a.seconds, "--threads",
            str(a.threads)]
    if case != CLIENT:
        extra = ["--plain"] if case == PLAIN else ["--serve", "127.0.0.1:0", "--play",
                                                   "--exit-when-done"]
        out = subprocess.run(base + extra, cwd=ROOT, check=True, capture_output=True,
                             text=True).stdout
        return steps_per_second(out), None
    port = free_port()
    server = subprocess.Popen(base + ["--serve", "127.0.0.1:%d" % port, "--exit-when-done"],
                              cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    line = server.stdout.readline()  # "viewer: open http://..." once listening
    if "http://" not in line:
        server.kill()
        raise SystemExit("colony_serve did not start serving: " + line)
    client = subprocess.run([probe, "ws://127.0.0.1:%d/" % port], cwd=ROOT, check=True,
                            capture_output=True, text=True).stdout
    out = server.stdout.read()
    if server.wait() != 0:
        raise SystemExit("colony_serve failed")
    m = re.search(r"([0-9.]+) frames/s", client)
    if not m:
        raise SystemExit("colony_viewer_probe printed no frames/s:\n" + client)
    return steps_per_second(out), float(m.group(1))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--scene", default="experiments/benchmarks/diffusion_10000.xml")
    p.add_argument("--seconds", type=float, default=30)
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--build", default="build")
    a = p.parse_args()
    rates = {c: [] for c in (PLAIN, NOBODY, CLIENT)}
    fps, loads = [], []
    for _ in range(a.repeat):
        for case in (PLAIN, NOBODY, CLIENT):
            loads.append(os.getloadavg()[0])
            rate, frames = run(a, case)
            rates[case].append(rate)
            if frames is not None:
                fps.append(frames)
    plain = statistics.median(rates[PLAIN])
    lines = ["", "| | robot-steps/s, median | each run | slower than plain |", "|---|---|---|---|"]
    for case in (PLAIN, NOBODY, CLIENT):
        median = statistics.median(rates[case])
        label = case if case != CLIENT else "%s at %.1f frames/s (median)" % (
            case, statistics.median(fps))
        lines.append("| %s | %s | %s | %s |" % (
            label, format(int(median), ","), ", ".join("%.0fk" % (r / 1e3) for r in rates[case]),
            "" if case == PLAIN else "%.1f%%" % (100 * (1 - median / plain))))
    lines += ["",
              "%s, %g simulated seconds, %d thread(s); %d interleaved repetitions of each, measured "
              "%s with a load average of %.1f to %.1f. Written by `tools/viewer_overhead.py --scene "
              "%s --seconds %g --threads %d --repeat %d`." % (
                  a.scene, a.seconds, a.threads, a.repeat, datetime.date.today().isoformat(),
                  min(loads), max(loads), a.scene, a.seconds, a.threads, a.repeat), ""]
    for doc in ("viewer.md", "benchmarks.md"):
        docblock.replace_block(os.path.join(ROOT, "docs", doc), "viewer overhead", lines)
    print("docs/viewer.md, docs/benchmarks.md: viewer overhead written")


if __name__ == "__main__":
    main()
