#!/usr/bin/env python3
"""Measures the start-up of the colony program (`colony version`: load the
program and its libraries, print, exit) and writes a table into
docs/benchmarks.md, between <!-- NAME results: begin --> and
<!-- NAME results: end -->.

    tools/startup_table.py NAME [--build LABEL=DIR ...] [--runs 200] [--rounds 3]

e.g. tools/startup_table.py startup --build before=/tmp/base/build --build after=build

Each build's bin/colony is started RUNS times per round, the builds (and
/bin/true, the floor of this way of measuring: Python's posix_spawn and
wait4) interleaved run by run, ROUNDS rounds. Wall time from spawn to the
end of wait4; CPU time (user + system) from wait4's rusage. The peak
resident set is GNU time's (/usr/bin/time -f %M, the median of 5 starts):
a child spawned from Python reports Python's own peak. The libraries are
those ldd lists for the program."""
import argparse
import datetime
import os
import shlex
import statistics
import subprocess
import sys
import time

import docblock

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "benchmarks.md")


def start(argv, devnull):
    """One start: (wall s, CPU s)."""
    t = time.perf_counter()
    pid = os.posix_spawn(argv[0], argv, os.environ,
                         file_actions=[(os.POSIX_SPAWN_DUP2, devnull, 1)])
    _, status, usage = os.wait4(pid, 0)
    wall = time.perf_counter() - t
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("%s exited with status %d" % (shlex.join(argv), os.waitstatus_to_exitcode(status)))
    return wall, usage.ru_utime + usage.ru_stime


def peak_kb(argv):
    """The median of 5 peak resident sets (KB) under GNU time."""
    peaks = []
    for _ in range(5):
        out = subprocess.run(["/usr/bin/time", "-f", "PEAK %M"] + argv, check=True,
                             capture_output=True, text=True).stderr
        peaks.append(int([l for l in out.splitlines() if l.startswith("PEAK ")][-1].split()[1]))
    return statistics.median(peaks)


def libraries(program):
    out = subprocess.run(["ldd", program], check=True, capture_output=True, text=True).stdout
    names = [line.split()[0] for line in out.splitlines() if line.strip()]
    return [n for n in names if not n.startswith("linux-vdso")]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("name")
    p.add_argument("--build", action="append", metavar="LABEL=DIR",
                   help="a build to measure (repeatable; default: build)")
    p.add_argument("--runs", type=int, default=200, help="starts per build per round")
    p.add_argument("--rounds", type=int, default=3)
    a = p.parse_args()
    builds = []
    for spec in a.build or ["build=build"]:
        label, _, folder = spec.partition("=")
        if not folder:
            sys.exit("--build takes LABEL=DIR, not '%s'" % spec)
        program = os.path.join(ROOT, folder, "bin", "colony")
        if not os.access(program, os.X_OK):
            sys.exit("no program %s (build the colony_app target there)" % program)
        builds.append((label, [program, "version"]))
    variants = builds + [("floor: /bin/true", ["/bin/true"])]
    samples = {label: [] for label, _ in variants}
    devnull = os.open(os.devnull, os.O_WRONLY)
    loads = []
    for _ in range(a.rounds):
        loads.append(os.getloadavg()[0])
        for _ in range(a.runs):
            for label, argv in variants:
                samples[label].append(start(argv, devnull))
    lines = ["",
             "| program | wall ms, median (10th to 90th percentile) | CPU ms, median | peak resident set | libraries loaded |",
             "|---|---|---|---|---|"]
    for label, argv in variants:
        walls = sorted(s[0] * 1e3 for s in samples[label])
        decile = statistics.quantiles(walls, n=10)
        cpu = statistics.median(s[1] * 1e3 for s in samples[label])
        rss = peak_kb(argv) / 1024
        libs = len(libraries(argv[0])) if argv[0] != "/bin/true" else ""
        name = label if argv[0] == "/bin/true" else "%s: `colony version`" % label
        lines.append("| %s | %.2f (%.2f to %.2f) | %.2f | %.1f MB | %s |" % (
            name, statistics.median(walls), decile[0], decile[-1], cpu, rss, libs))
    lines += ["",
              "%d starts of each, in %d rounds, interleaved; measured %s with a load average of %.1f to "
              "%.1f before the rounds; written by `tools/startup_table.py %s`." % (
                  a.runs * a.rounds, a.rounds, datetime.date.today().isoformat(), min(loads),
                  max(loads), shlex.join(sys.argv[1:])), ""]
    docblock.replace_block(DOC, "%s results" % a.name, lines)


if __name__ == "__main__":
    main()
