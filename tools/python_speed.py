#!/usr/bin/env python3
"""Compares stepping from Python (colony.Simulation.run, the module in
BUILD/python) with `colony run` on the same file, interleaved, REPEAT times
at each thread count, and writes the medians into docs/python.md (between
<!-- python speed: begin --> and <!-- python speed: end -->). Runs under
Debian's /usr/bin/python3 (numpy and the module's build). Fails if the two
end in different states.

    /usr/bin/python3 tools/python_speed.py [--scene experiments/benchmarks/diffusion_1000.xml]
                                           [--threads 1,2] [--repeat 5] [--build build]"""
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


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--scene", default="experiments/benchmarks/diffusion_1000.xml")
    p.add_argument("--threads", default="1,2")
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--build", default="build")
    a = p.parse_args()
    sys.path.insert(0, os.path.join(ROOT, a.build, "python"))
    import colony
    exe = os.path.join(ROOT, a.build, "bin", "colony")
    lines = ["", "| threads | `colony run` (robot-steps/s) | `sim.run()` (robot-steps/s) | state hash |",
             "|---|---|---|---|"]
    loads = []
    for threads in [int(t) for t in a.threads.split(",")]:
        cli, py, hashes = [], [], set()
        for _ in range(a.repeat):
            loads.append(os.getloadavg()[0])
            out = subprocess.run([exe, "run", a.scene, "--threads", str(threads), "--out",
                                  "/tmp/colony_python_speed", "--overwrite"], cwd=ROOT, check=True,
                                 capture_output=True, text=True).stdout
            cli.append(float(re.search(r"\(([0-9.e+]+) robot-steps/s", out).group(1)))
            hashes.add(re.search(r"final state hash ([0-9a-f]+)", out).group(1))
            sim = colony.Simulation(os.path.join(ROOT, a.scene), threads=threads)
            t0 = time.perf_counter()
            ticks = sim.run()
            py.append(ticks * sim.robot_count / (time.perf_counter() - t0))
            hashes.add(sim.state_hash())
        if len(hashes) != 1:
            raise SystemExit("colony run and sim.run ended in different states: %s" % sorted(hashes))
        lines.append("| %d | %s | %s | `%s` |" % (threads, format(int(statistics.median(cli)), ","),
                                                  format(int(statistics.median(py)), ","),
                                                  hashes.pop()))
    lines += ["",
              "%s, medians of %d interleaved runs of each, measured %s with a load average of %.1f "
              "to %.1f. `colony run`'s figure is its own robot-steps/s line (the steps alone); "
              "`sim.run()`'s is ticks x robots / the call's wall time. Written by "
              "`/usr/bin/python3 tools/python_speed.py --scene %s --threads %s --repeat %d`." % (
                  a.scene, a.repeat, datetime.date.today().isoformat(), min(loads), max(loads),
                  a.scene, a.threads, a.repeat), ""]
    docblock.replace_block(os.path.join(ROOT, "docs", "python.md"), "python speed", lines)
    print("docs/python.md: python speed written")


if __name__ == "__main__":
    main()
