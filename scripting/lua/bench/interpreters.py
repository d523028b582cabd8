#!/usr/bin/env python3
"""Is any Lua interpreter fast enough for the 3x target at 10,000 robots?

Times experiments/lua/diffusion.lua's step() alone (scripting/lua/bench/step_alone.lua)
on each interpreter found (lua5.3, lua5.4, luajit, and luajit -joff: its interpreter without the
JIT) at 10, 1,000 and 10,000 robots, with two cut-down copies of the script (an empty step(); the
step without its loop over the readings), and, with --bench, the whole robot-step of the C++ and
Lua diffusion scenes at 10,000 robots in the same rounds. Rounds are interleaved; writes markdown
tables of the medians (the rounds' values in brackets) between <!-- lua interpreters: begin --> and
<!-- lua interpreters: end --> in scripting/lua/BENCHMARK-NOTES.md, and prints them. Run from the
project's root:

  scripting/lua/bench/interpreters.py --rounds 3 --bench build/bin/colony_bench

Interpreters are not build dependencies: `apt-get install lua5.3 lua5.4 luajit`.
"""
import argparse
import datetime
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                                "tools"))
import docblock  # noqa: E402  (tools/docblock.py)

NOTES = "scripting/lua/BENCHMARK-NOTES.md"
SCRIPT = "experiments/lua/diffusion.lua"
HARNESS = "scripting/lua/bench/step_alone.lua"
INTERPRETERS = [("Lua 5.3", ["lua5.3"]), ("Lua 5.4", ["lua5.4"]), ("LuaJIT", ["luajit"]),
                ("LuaJIT -joff", ["luajit", "-joff"])]
SIZES = [10, 1000, 10000]


def variants(folder):
    """The script, and copies with an empty step() and with step() minus the readings loop."""
    source = open(SCRIPT).read()
    step_start = source.index("function step()")
    step_end = source.index("function reset()")
    step = source[step_start:step_end]
    loop_start = step.index("   for i = 1, n do")
    loop_end = step.index("   x, y = x / n")
    cuts = {
        "empty step()": source[:step_start] + "function step()\nend\n\n" + source[step_end:],
        "step() without the readings loop":
            source[:step_start] + step[:loop_start] + step[loop_end:] + source[step_end:],
    }
    paths = {"diffusion.lua": SCRIPT}
    for name, text in cuts.items():
        path = os.path.join(folder, re.sub(r"\W+", "_", name) + ".lua")
        with open(path, "w") as f:
            f.write(text)
        paths[name] = path
    return paths


def step_alone(command, script, n, steps):
    # The same number of steps at every swarm size (at least 200 ticks).
    ticks = max(200, steps // n)
    out = subprocess.run(command + [HARNESS, script, str(n), str(ticks)], check=True,
                         capture_output=True, text=True).stdout
    return float(re.search(r"ns_per_step=([0-9.]+)", out).group(1))


def robot_step(bench, scene):
    out = subprocess.run([bench, scene, "--threads", "2", "--repeat", "1"], check=True,
                         capture_output=True, text=True).stdout
    return float(re.search(r"cpu_ns_per_robot_step=([0-9.]+)", out).group(1))


def cell(values):
    return f"{statistics.median(values):,.0f} ({' / '.join(f'{v:,.0f}' for v in values)})"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--steps", type=int, default=2_000_000,
                        help="robot-steps per timing (ticks = steps / robots, at least 200)")
    parser.add_argument("--bench", help="colony_bench: also time the whole robot-step of "
                        "diffusion_10000 and diffusion_lua_10000")
    args = parser.parse_args()
    if not os.path.exists(SCRIPT):
        sys.exit(f"{SCRIPT} not found: run from the project's root")
    found = [(name, cmd) for name, cmd in INTERPRETERS if shutil.which(cmd[0])]
    if not found:
        sys.exit("no Lua interpreter found (apt-get install lua5.3 lua5.4 luajit)")
    load = os.getloadavg()[0]
    folder = tempfile.mkdtemp(prefix="lua-interpreters-")
    scripts = variants(folder)
    results = {}
    scenes = {"diffusion_10000 (C++ controller)": "experiments/benchmarks/diffusion_10000.xml",
              "diffusion_lua_10000 (Lua, Lua 5.3 host)":
                  "experiments/lua/benchmarks/diffusion_lua_10000.xml"}
    for _ in range(args.rounds):
        for name, cmd in found:
            for n in SIZES:
                results.setdefault(("diffusion.lua", name, n), []).append(
                    step_alone(cmd, SCRIPT, n, args.steps))
            for variant in ("empty step()", "step() without the readings loop"):
                results.setdefault((variant, name, 10), []).append(
                    step_alone(cmd, scripts[variant], 10, args.steps))
        if args.bench:
            for label, scene in scenes.items():
                results.setdefault(("bench", label), []).append(robot_step(args.bench, scene))
    shutil.rmtree(folder)

    out = []
    out.append("The step alone (ns per step), experiments/lua/diffusion.lua:\n")
    out.append("| interpreter | " + " | ".join(f"{n:,} robots" for n in SIZES) + " |")
    out.append("|---|" + "---:|" * len(SIZES))
    for name, _ in found:
        out.append(f"| {name} | " +
                   " | ".join(cell(results[("diffusion.lua", name, n)]) for n in SIZES) + " |")
    out.append("\nCut-down copies of the script, 10 robots (ns per step):\n")
    out.append("| interpreter | empty step() | step() without the readings loop | whole step() |")
    out.append("|---|---:|---:|---:|")
    for name, _ in found:
        out.append(f"| {name} | {cell(results[('empty step()', name, 10)])} | "
                   f"{cell(results[('step() without the readings loop', name, 10)])} | "
                   f"{cell(results[('diffusion.lua', name, 10)])} |")
    if args.bench:
        out.append("\nThe whole robot-step in Colony, same rounds (CPU ns per robot-step, "
                   "colony_bench --threads 2 --repeat 1):\n")
        out.append("| scene | CPU ns per robot-step |")
        out.append("|---|---:|")
        for label in scenes:
            out.append(f"| {label} | {cell(results[('bench', label)])} |")
    command = " ".join(["scripting/lua/bench/interpreters.py", f"--rounds {args.rounds}"] +
                       ([f"--steps {args.steps}"] if args.steps != 2_000_000 else []) +
                       ([f"--bench {args.bench}"] if args.bench else []))
    out.append(f"\n{args.rounds} interleaved rounds, {args.steps:,} steps per timing, measured "
               f"{datetime.date.today().isoformat()} with a load average of {load:.1f} before the "
               f"runs; written by `{command}`.\n")
    text = "\n".join(out)
    print(text)
    docblock.replace_block(NOTES, "lua interpreters", [""] + text.split("\n"))


if __name__ == "__main__":
    main()
