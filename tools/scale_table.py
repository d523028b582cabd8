#!/usr/bin/env python3
"""Before/after figures of loading, memory and stepping at scale (issue 20),
written into docs/benchmarks.md between <!-- scale results: begin --> and
<!-- scale results: end -->.

    tools/scale_table.py --before /path/to/old/build [--after build]
        [--scene experiments/benchmarks/diffusion_1000000.xml ...]
        [--repeat 3] [--ticks 5] [--threads 2] [--block scale]

For each scene it runs `colony_bench SCENE --repeat 1 --ticks T --threads N`
of the "before" build and of the "after" build in turn, K times (interleaved,
so both see the same load from other programs), and reports the median of
each figure, the state hashes, and the load average seen before the runs.
Load time is given as wall-clock seconds and as the CPU seconds the process
spent loading (steadier when other programs share the cores).
"before" is a build of an earlier commit (e.g. `git archive COMMIT | tar -x
-C DIR`, built the same way); colony_bench of that build may not report the
teardown time or the load's CPU time (shown as -)."""
import argparse
import datetime
import os
import statistics
import subprocess

import docblock

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "benchmarks.md")


def bench(build, scene, ticks, threads):
    exe = os.path.join(ROOT, build, "bin", "colony_bench")
    out = subprocess.run([exe, scene, "--repeat", "1", "--ticks", str(ticks), "--threads",
                          str(threads)], cwd=ROOT, check=True, capture_output=True,
                         text=True).stdout
    line = [l for l in out.splitlines() if l.startswith("RESULT ")][-1]
    return dict(kv.split("=", 1) for kv in line.split()[1:])


def median(runs, key):
    values = [float(r[key]) for r in runs if key in r]
    return statistics.median(values) if values else None


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--before", required=True)
    p.add_argument("--after", default="build")
    p.add_argument("--scene", action="append")
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--ticks", type=int, default=5)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--block", default="scale",
                   help="the table's block in docs/benchmarks.md: <!-- BLOCK results: begin -->")
    a = p.parse_args()
    scenes = a.scene or ["experiments/benchmarks/diffusion_10000.xml",
                         "experiments/benchmarks/diffusion_100000.xml",
                         "experiments/benchmarks/diffusion_1000000.xml"]
    lines = ["",
             "| scene | build | load s | load CPU s | teardown s | bytes/robot (peak) | bytes/robot (after load) "
             "| CPU ns per robot-step | robot-steps/s | state hash |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    loads = []
    for scene in scenes:
        runs = {"before": [], "after": []}
        for _ in range(a.repeat):
            for name, build in (("before", a.before), ("after", a.after)):
                loads.append(os.getloadavg()[0])
                runs[name].append(bench(build, scene, a.ticks, a.threads))
        for name in ("before", "after"):
            r = runs[name]
            hashes = sorted({x["state_hash"] for x in r})
            teardown = median(r, "teardown_s_median")
            load_cpu = median(r, "load_cpu_s_median")
            lines.append("| %s | %s | %.2f | %s | %s | %s | %s | %s | %s | `%s` |" % (
                r[0]["scene"], name, median(r, "load_s_median"),
                "-" if load_cpu is None else "%.2f" % load_cpu,
                "-" if teardown is None else "%.2f" % teardown,
                format(round(median(r, "bytes_per_robot")), ","),
                format(round(median(r, "load_bytes_per_robot")), ","),
                format(round(median(r, "cpu_ns_per_robot_step")), ","),
                format(round(median(r, "steps_per_s_median")), ","), "`, `".join(hashes)))
    lines += ["",
              "Medians of %d interleaved runs of each build, %d ticks, %d threads, measured %s "
              "with a load average of %.1f to %.1f before the runs; written by "
              "`tools/scale_table.py --before %s --repeat %d --ticks %d --threads %d%s%s`." % (
                  a.repeat, a.ticks, a.threads, datetime.date.today().isoformat(), min(loads),
                  max(loads), a.before, a.repeat, a.ticks, a.threads,
                  "".join(" --scene " + s for s in (a.scene or [])),
                  "" if a.block == "scale" else " --block " + a.block), ""]
    docblock.replace_block(DOC, "%s results" % a.block, lines)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
