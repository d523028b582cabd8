#!/usr/bin/env python3
"""Measures the batched Python controller (examples/python/numpy_diffusion.py, one numpy call per
tick for all robots) against the C++ diffusion controller on the same scene: `colony run` of
experiments/benchmarks/diffusion_10000.xml (C++) and of diffusion_numpy_10000.xml (numpy), and
both stepped tick by tick from Python (colony.Simulation, the module in BUILD/python; each tick
timed), interleaved, REPEAT times each, at THREADS threads; writes the medians into docs/benchmarks.md and
docs/python.md (between <!-- python batch speed: begin --> and <!-- python batch speed: end -->).
Runs under Debian's /usr/bin/python3. Fails if a controller's runs end in different states (from
one repetition to the next, or between `colony run` and Python).

    /usr/bin/python3 tools/python_batch_speed.py [--threads 2] [--repeat 5] [--seconds 20]
                                                 [--build build]"""
import argparse
import datetime
import os
import re
import statistics
import subprocess
import sys
import time

import docblock

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CPP = "experiments/benchmarks/diffusion_10000.xml"
NUMPY = "experiments/benchmarks/diffusion_numpy_10000.xml"


def colony_run(exe, scene, threads, seconds):
    out = subprocess.run([exe, "run", scene, "--threads", str(threads), "--set",
                          "framework.experiment.length=%g" % seconds, "--out",
                          "/tmp/colony_python_batch_speed", "--overwrite"], cwd=ROOT, check=True,
                         capture_output=True, text=True).stdout
    rate = float(re.search(r"\(([0-9.e+]+) robot-steps/s", out).group(1))
    return rate, re.search(r"final state hash ([0-9a-f]+)", out).group(1)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--seconds", type=float, default=20, help="simulated seconds per run")
    p.add_argument("--build", default="build")
    a = p.parse_args()
    sys.path.insert(0, os.path.join(ROOT, a.build, "python"))
    import colony
    exe = os.path.join(ROOT, a.build, "bin", "colony")
    rates = {"cpp": [], "numpy": [], "cpp_py": [], "numpy_py": []}
    fast = {"cpp_py": [], "numpy_py": []}  # every tick's wall time, stepped from Python
    hashes = {"cpp": set(), "numpy": set()}
    loads = []
    robots = ticks = 0
    for _ in range(a.repeat):
        loads.append(os.getloadavg()[0])
        rate, h = colony_run(exe, CPP, a.threads, a.seconds)
        rates["cpp"].append(rate)
        hashes["cpp"].add(h)
        rate, h = colony_run(exe, NUMPY, a.threads, a.seconds)
        rates["numpy"].append(rate)
        hashes["numpy"].add(h)
        for name, scene in (("cpp_py", CPP), ("numpy_py", NUMPY)):
            sim = colony.Simulation(os.path.join(ROOT, scene), threads=a.threads,
                                    set={"framework.experiment.length": a.seconds})
            ticks, tick_times = 0, []
            while not sim.done:
                t0 = time.perf_counter()
                sim.step()
                tick_times.append(time.perf_counter() - t0)
                ticks += 1
            robots = sim.robot_count
            rates[name].append(ticks * robots / sum(tick_times))
            fast[name].extend(tick_times)
            hashes[name.split("_")[0]].add(sim.state_hash())
            del sim
    loads.append(os.getloadavg()[0])
    for name, found in hashes.items():
        if len(found) != 1:
            raise SystemExit("%s: the runs ended in different states: %s" % (name, sorted(found)))
    med = {k: statistics.median(v) for k, v in rates.items()}

    def cell(k):
        return "%s (%s to %s)" % (format(int(med[k]), ","), format(int(min(rates[k])), ","),
                                  format(int(max(rates[k])), ","))

    def quick(k):
        # The tenth percentile of the tick times: what the machine gives between other loads.
        t = sorted(fast[k])[len(fast[k]) // 10]
        return format(int(robots / t), ",")

    numpy_row = "numpy `Diffusion` (`<python_batch_controller>`)"
    lines = ["",
             "| controller | run by | robot-steps/s, median (min to max) | per robot-step | "
             "fastest ticks (10th percentile) | state hash |",
             "|---|---|---|---|---|---|",
             "| C++ `diffusion` | `colony run` | %s | %.0f ns | | `%s` |" % (
                 cell("cpp"), 1e9 / med["cpp"], min(hashes["cpp"])),
             "| C++ `diffusion` | `sim.step()` in Python | %s | %.0f ns | %s | `%s` |" % (
                 cell("cpp_py"), 1e9 / med["cpp_py"], quick("cpp_py"), min(hashes["cpp"])),
             "| %s | `colony run` | %s | %.0f ns | | `%s` |" % (
                 numpy_row, cell("numpy"), 1e9 / med["numpy"], min(hashes["numpy"])),
             "| %s | `sim.step()` in Python | %s | %.0f ns | %s | `%s` |" % (
                 numpy_row, cell("numpy_py"), 1e9 / med["numpy_py"], quick("numpy_py"),
                 min(hashes["numpy"])),
             "",
             "%d robots, %d ticks, %d threads; %s (C++) and %s (numpy), %d interleaved runs of "
             "each, measured %s with a load average of %.1f to %.1f before the runs (on 2 cores). "
             "`colony run`'s figure is its own robot-steps/s line (the steps "
             "alone); `sim.step()`'s is ticks x robots / the sum of the ticks' wall times; the "
             "fastest-ticks column is robots / the 10th percentile of every tick's wall time over "
             "all runs of that variant. The numpy controller's hash differs from the C++ one's: it "
             "sums the readings in another order (a matrix-vector product), so the robots' paths "
             "part after a few ticks. Written by `/usr/bin/python3 tools/python_batch_speed.py "
             "--threads %d --repeat %d --seconds %g`." % (
                 robots, ticks, a.threads, CPP, NUMPY, a.repeat,
                 datetime.date.today().isoformat(), min(loads), max(loads), a.threads, a.repeat,
                 a.seconds),
             ""]
    for doc in ("benchmarks.md", "python.md"):
        docblock.replace_block(os.path.join(ROOT, "docs", doc), "python batch speed", lines)
    print("\n".join(lines))
    print("docs/benchmarks.md, docs/python.md: python batch speed written")


if __name__ == "__main__":
    main()
