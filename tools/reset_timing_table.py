#!/usr/bin/env python3
"""Runs colony_reset_timing (examples/evolution/reset_timing.cpp) on the
diffusion scenes and writes the table of its medians into docs/embedding.md
(between <!-- reset timing: begin --> and <!-- reset timing: end -->).

    tools/reset_timing_table.py [--repeats 20] [--build build]

Fails if a Reset did not give the state of a fresh load with its seed."""
import argparse
import datetime
import os
import re
import subprocess

import docblock

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = ["experiments/diffusion.xml", "experiments/benchmarks/diffusion_1000.xml",
          "experiments/benchmarks/diffusion_10000.xml"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--repeats", type=int, default=20)
    p.add_argument("--build", default="build")
    a = p.parse_args()
    exe = os.path.join(ROOT, a.build, "bin", "colony_reset_timing")
    lines = ["", "| scene | robots | load | delete | Reset |", "|---|---|---|---|---|"]
    loads = []
    for scene in SCENES:
        loads.append(os.getloadavg()[0])
        out = subprocess.run([exe, scene, "--repeats", str(a.repeats)], cwd=ROOT, check=True,
                             capture_output=True, text=True).stdout
        robots = re.search(r": (\d+) robots", out).group(1)
        load, delete = re.search(r"load \(read the file, build\): ([0-9.]+) ms; delete: ([0-9.]+) ms",
                                 out).groups()
        reset = re.search(r"Reset \(delete, build with a new seed; no file read\): ([0-9.]+) ms",
                          out).group(1)
        if "a fresh load with its seed: yes" not in out:
            raise SystemExit("%s: a Reset differs from a fresh load:\n%s" % (scene, out))
        lines.append("| %s | %s | %s ms | %s ms | %s ms |" % (scene, format(int(robots), ","), load,
                                                             delete, reset))
    lines += ["",
              "Medians of %d, one thread, measured %s with a load average of %.1f to %.1f; every "
              "Reset gave the state of a fresh load with its seed. Written by "
              "`tools/reset_timing_table.py --repeats %d`." % (
                  a.repeats, datetime.date.today().isoformat(), min(loads), max(loads), a.repeats),
              ""]
    docblock.replace_block(os.path.join(ROOT, "docs", "embedding.md"), "reset timing", lines)
    print("docs/embedding.md: reset timing written")


if __name__ == "__main__":
    main()
