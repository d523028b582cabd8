"""The Python examples (examples/python/) and the experiment files that use Python controllers,
each run in a shortened form."""

import os
import re
import subprocess
import sys

import pytest

from conftest import colony_program, colony_run

EXAMPLES = "examples/python"


def python(args):
    out = subprocess.run([sys.executable, *args], capture_output=True, text=True,
                         env=dict(os.environ))
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_evolution_strategy_shortened():
    out = python([f"{EXAMPLES}/evolution_strategy.py", "--generations", "2", "--population", "4",
                  "--seconds", "3", "--robots", "10"])
    lines = out.splitlines()
    assert lines[0].startswith("start:") and lines[-1].startswith("best:")
    assert len([l for l in lines if l.startswith("generation")]) == 2
    start = float(re.search(r"coverage ([0-9.]+)", lines[0]).group(1))
    best = float(re.search(r"coverage ([0-9.]+)", lines[-1]).group(1))
    # Coverage is a share of the floor's cells: 10 robots for 3 s see some, far from all.
    assert 0 < start <= best < 1
    assert "9 runs in one process" in lines[-1]


def test_plot_sweep_writes_a_png(tmp_path):
    folder = tmp_path / "sweep"
    subprocess.run([colony_program(), "sweep", "experiments/diffusion.xml", "--quiet", "--jobs",
                    "2", "--param", "controllers.diffusion[dc].params.velocity=0.02,0.1",
                    "--param", "arena.distribute.entity.quantity=5,10",
                    "--param", "framework.experiment.length=2", "--seeds", "1..2",
                    "--out", str(folder)], check=True)
    png = tmp_path / "sweep.png"
    out = python([f"{EXAMPLES}/plot_sweep.py", str(folder), "--out", str(png)])
    assert "mean_displacement against controllers.diffusion[dc].params.velocity over 8 runs" in out
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20000  # two panels of lines and text
    # A metric that is not there is refused, naming those that are.
    bad = subprocess.run([sys.executable, f"{EXAMPLES}/plot_sweep.py", str(folder), "--metric",
                          "nope", "--out", str(png)], capture_output=True, text=True)
    assert bad.returncode == 2 and "no metric 'nope'" in bad.stderr


@pytest.mark.parametrize("xml, sets", [
    (f"{EXAMPLES}/batched_diffusion.xml", ["--set", "framework.experiment.length=3"]),
    ("experiments/benchmarks/diffusion_numpy_10000.xml",
     ["--set", "framework.experiment.length=1", "--set", "arena.distribute.entity.quantity=200"]),
])
def test_python_experiment_files_run(xml, sets):
    final, out = colony_run([xml, "--threads", "2", *sets])
    assert re.search(r"final state hash [0-9a-f]{16}", out)
