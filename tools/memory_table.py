#!/usr/bin/env python3
"""Accounts for the memory of a robot: runs colony_bench on a scene under
valgrind's massif (heap profiler), takes the heap at its peak, sums it by the
function that allocated it (and that function's caller), divides by the
robots and writes the table into docs/design-notes.md between
<!-- memory per robot: begin --> and <!-- memory per robot: end -->.

    tools/memory_table.py [SCENE.xml] [--ticks 3] [--build build] [--block NAME]

--block names the markers (default "memory per robot"); --build may be
another build of Colony (an absolute path), e.g. of an earlier commit, to
write a "before" table beside the current one.

Default scene: experiments/benchmarks/diffusion_10000.xml (the one the test
suite's memory budget checks). It also runs colony_bench once without valgrind
(median of 3 loads) for the resident-set figure that budget uses (peak
resident set growth per robot), so the heap table and the budget can be compared."""
import argparse
import collections
import datetime
import os
import re
import subprocess
import tempfile

import docblock

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "design-notes.md")


def short(fn):
    """A function's name without namespaces' noise, argument lists or library."""
    fn = re.sub(r" \(in [^)]*\)$", "", fn)
    fn = re.sub(r"^0x[0-9A-Fa-f]+: ", "", fn)
    fn = fn.replace("colony::", "").replace("(anonymous namespace)::", "")
    fn = fn.replace("std::__cxx11::", "std::")
    # Drop argument lists and template arguments, innermost first.
    for _ in range(8):
        fn = re.sub(r"<[^<>]*>", "", fn)
        fn = re.sub(r"\([^()]*\)", "", fn)
    return fn.strip()


def peak_tree(path):
    """(useful heap bytes, extra bytes, [(depth, bytes, function)]) of the peak snapshot."""
    with open(path) as f:
        text = f.read()
    snapshots = text.split("#-----------\nsnapshot=")
    for snap in snapshots:
        if "heap_tree=peak" not in snap:
            continue
        heap = int(re.search(r"mem_heap_B=(\d+)", snap).group(1))
        extra = int(re.search(r"mem_heap_extra_B=(\d+)", snap).group(1))
        nodes = []
        for line in snap.split("heap_tree=peak\n", 1)[1].splitlines():
            m = re.match(r"^( *)n\d+: (\d+) (.*)$", line)
            if m:
                nodes.append((len(m.group(1)), int(m.group(2)), m.group(3)))
        return heap, extra, nodes
    raise SystemExit("%s: no peak snapshot" % path)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("scene", nargs="?", default="experiments/benchmarks/diffusion_10000.xml")
    p.add_argument("--ticks", type=int, default=3)
    p.add_argument("--build", default="build")
    p.add_argument("--block", default="memory per robot")
    a = p.parse_args()
    exe = os.path.join(ROOT, a.build, "bin", "colony_bench")
    args = [exe, a.scene, "--ticks", str(a.ticks), "--threads", "1", "--repeat"]
    out = subprocess.run(args + ["3"], cwd=ROOT, check=True, capture_output=True, text=True).stdout
    result = dict(kv.split("=", 1) for kv in [l for l in out.splitlines()
                                              if l.startswith("RESULT ")][-1].split()[1:])
    robots = int(result["robots"])
    with tempfile.TemporaryDirectory() as tmp:
        massif = os.path.join(tmp, "massif.out")
        subprocess.run(["valgrind", "--tool=massif", "--massif-out-file=" + massif, "--depth=8",
                        "--threshold=0.2"] + args + ["1"], cwd=ROOT, check=True, capture_output=True)
        heap, extra, nodes = peak_tree(massif)
    # Each allocating function (depth 1) with its caller (depth 2, the
    # largest), summed over the call sites of the same names.
    sums = collections.OrderedDict()
    i = 0
    while i < len(nodes):
        depth, size, fn = nodes[i]
        if depth == 1:
            caller = ""
            if i + 1 < len(nodes) and nodes[i + 1][0] == 2:
                caller = short(nodes[i + 1][2])
            name = short(fn)
            key = name if name.startswith("in ") else "%s, from %s" % (name, caller or "-")
            sums[key] = sums.get(key, 0) + size
        i += 1
    rows = sorted(sums.items(), key=lambda kv: -kv[1])
    lines = ["",
             "| allocated in (from) | bytes per robot | share of the heap |",
             "|---|---|---|"]
    for key, size in rows:
        if size / robots < 1:
            continue
        lines.append("| `%s` | %.0f | %.1f%% |" % (key.replace("|", "\\|"), size / robots,
                                                  100.0 * size / heap))
    lines.append("| malloc's own overhead (headers, rounding) | %.0f | |" % (extra / robots))
    lines.append("| **heap at its peak, in all** | **%.0f** | |" % ((heap + extra) / robots))
    lines += ["",
              "Heap at its peak (valgrind massif), per robot: %s, %d robots, %d ticks, 1 thread. "
              "The memory budget's figure for the same run (peak resident set growth per robot, "
              "colony_bench, median of 3 loads): **%s bytes**; it counts pages touched, not reserved and untouched "
              "heap. Measured %s; written by `tools/memory_table.py %s`." % (
                  result["scene"], robots, a.ticks, result["bytes_per_robot"],
                  datetime.date.today().isoformat(),
                  " ".join([a.scene] + (["--build", a.build] if a.build != "build" else []) +
                           (["--block", "'%s'" % a.block] if a.block != "memory per robot" else []))),
              ""]
    docblock.replace_block(DOC, a.block, lines)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
