"""Shared helpers for the Python module's tests, run by ctest (python/CMakeLists.txt) from the
source tree with PYTHONPATH at the build tree's python/ and COLONY_PROGRAM set to the colony
program."""

import os
import re
import subprocess

import pytest

DIFFUSION = "experiments/diffusion.xml"


def colony_program():
    program = os.environ.get("COLONY_PROGRAM")
    if not program or not os.path.exists(program):
        pytest.fail("COLONY_PROGRAM must name the colony program (ctest sets it)")
    return program


def colony_run(args, cwd=None):
    """Runs `colony run ARGS --quiet`-less (the closing lines are needed) and returns its final
    state hash and its stdout."""
    out = subprocess.run([colony_program(), "run", *args], capture_output=True, text=True,
                         cwd=cwd, check=False)
    assert out.returncode == 0, out.stderr
    match = re.search(r"final state hash ([0-9a-f]{16})", out.stdout)
    assert match, out.stdout
    return match.group(1), out.stdout
