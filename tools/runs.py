"""Runs an experiment of this checkout with `colony run` and reads its
metrics: shared by the scripts that write results into docs/
(tools/*_results.py)."""
import csv
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def last_row(path):
    """The last row of the CSV file at PATH, as a dict."""
    with open(path) as f:
        return list(csv.DictReader(f))[-1]


def last_metrics(build, experiment, seed, out, sets=()):
    """The last row of metrics.csv of `colony run EXPERIMENT --seed SEED`
    (EXPERIMENT relative to the checkout; the run folder is OUT; SETS are
    PATH=VALUE overrides), as a dict."""
    colony = os.path.join(ROOT, build, "bin", "colony")
    extra = [arg for s in sets for arg in ("--set", s)]
    subprocess.run([colony, "run", experiment, "--seed", str(seed), "--out", out, "--overwrite", "--quiet"]
                   + extra, cwd=ROOT, check=True)
    return last_row(os.path.join(out, "metrics.csv"))
