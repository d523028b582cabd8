"""Runs an experiment of this checkout with `colony run` and reads its
metrics: shared by the scripts that write results into docs/
(tools/*_results.py)."""
import csv
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def last_metrics(build, experiment, seed, out):
    """The last row of metrics.csv of `colony run EXPERIMENT --seed SEED`
    (EXPERIMENT relative to the checkout; the run folder is OUT), as a dict."""
    colony = os.path.join(ROOT, build, "bin", "colony")
    subprocess.run([colony, "run", experiment, "--seed", str(seed), "--out", out, "--overwrite", "--quiet"],
                   cwd=ROOT, check=True)
    with open(os.path.join(out, "metrics.csv")) as f:
        return list(csv.DictReader(f))[-1]
