#!/usr/bin/env python3
"""Counts the instructions colony_bench executes on benchmark scenes, under
valgrind's callgrind, for two builds, and writes the table into
docs/benchmarks.md between <!-- NAME results: begin --> and
<!-- NAME results: end -->.

    tools/instruction_table.py NAME SCENE.xml:TICKS [SCENE.xml:TICKS ...]
                               --against BUILD [--build build]

e.g. tools/instruction_table.py round7_instructions experiments/benchmarks/diffusion_10000.xml:30
         --against /path/to/old/build
Each run is `colony_bench SCENE --threads 1 --repeat 1 --ticks TICKS` (the load
and the teardown included). A count of instructions is the same from run to
run whatever else the machine does, so small changes show where timings on a
shared machine vary by 10%; it is not time (a cache miss counts as one
instruction). Needs valgrind."""
import argparse
import datetime
import os
import re
import shlex
import subprocess
import sys
import tempfile

import docblock

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "benchmarks.md")


def count(build, scene, ticks):
    """(instructions, state hash) of one run of `build`'s colony_bench."""
    exe = os.path.join(ROOT, build, "bin", "colony_bench")
    with tempfile.TemporaryDirectory() as tmp:
        run = subprocess.run(["valgrind", "--tool=callgrind",
                              "--callgrind-out-file=" + os.path.join(tmp, "callgrind.out"),
                              exe, scene, "--threads", "1", "--repeat", "1", "--ticks", str(ticks)],
                             cwd=ROOT, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit("%s on %s failed:\n%s" % (exe, scene, run.stderr[-2000:]))
    collected = re.search(r"Collected : (\d+)", run.stderr)
    state = re.search(r"state_hash=([0-9a-f]+)", run.stdout)
    if not collected or not state:
        sys.exit("%s on %s: no instruction count or state hash in its output" % (exe, scene))
    return int(collected.group(1)), state.group(1)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("name")
    p.add_argument("scenes", nargs="+", metavar="SCENE.xml:TICKS")
    p.add_argument("--against", required=True, metavar="BUILD")
    p.add_argument("--build", default="build")
    a = p.parse_args()
    lines = ["", "| scene | ticks | instructions before | after | change | state hash before | after |",
             "|---|---|---|---|---|---|---|"]
    for item in a.scenes:
        scene, sep, ticks = item.rpartition(":")
        if not sep or not ticks.isdigit() or int(ticks) < 1:
            sys.exit("%s: give each scene as SCENE.xml:TICKS (TICKS a whole number >= 1)" % item)
        before, hash_before = count(a.against, scene, int(ticks))
        after, hash_after = count(a.build, scene, int(ticks))
        name = os.path.splitext(os.path.basename(scene))[0]
        lines.append("| %s | %s | %s | %s | %+.1f%% | `%s` | %s |" % (
            name, ticks, format(before, ","), format(after, ","), 100.0 * (after - before) / before,
            hash_before, "same" if hash_after == hash_before else "`%s`" % hash_after))
    lines += ["", "Instructions executed by one run of each build (valgrind --tool=callgrind, one thread, "
              "the load and teardown included), counted %s; written by `tools/instruction_table.py %s`." % (
                  datetime.date.today().isoformat(), shlex.join(sys.argv[1:])), ""]
    docblock.replace_block(DOC, "%s results" % a.name, lines)
    print("docs/benchmarks.md: %s written" % a.name)


if __name__ == "__main__":
    main()
