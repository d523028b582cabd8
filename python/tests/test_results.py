"""colony.results: run and sweep folders made by `colony run` and `colony sweep` into pandas."""

import json
import subprocess

import numpy as np
import pandas as pd
import pytest

import colony
from conftest import DIFFUSION, colony_program, colony_run

SETS = ["--set", "arena.distribute.entity.quantity=12", "--set", "framework.experiment.length=2"]


@pytest.mark.parametrize("output, file", [
    (["--set", "output.format=csv"], "trajectories.csv"),
    (["--set", "output.format=csv", "--set", "output.compress=gzip"], "trajectories.csv.gz"),
    (["--set", "output.format=hdf5"], "trajectories.h5"),
])
def test_load_run(tmp_path, output, file):
    folder = tmp_path / "run"
    final_hash, _ = colony_run([DIFFUSION, "--seed", "2", "--threads", "1", *SETS,
                                "--set", "output.trajectories_every=5", *output,
                                "--out", str(folder)])
    assert (folder / file).exists()
    run = colony.results.load_run(folder)
    assert run.summary["completed"] is True
    assert run.summary["final_state_hash"] == final_hash
    assert run.summary["robots"] == 12
    # metrics.csv: a row at tick 0 then every 10 ticks (<output metrics_every="10">).
    assert list(run.metrics["tick"]) == [0, 10, 20]
    assert run.metrics["tick"].dtype == np.int64
    assert run.metrics["mean_displacement"].dtype == np.float64
    assert run.metrics["mean_displacement"].iloc[-1] == pytest.approx(
        run.summary["metrics"]["mean_displacement"], rel=1e-12)
    # Trajectories: 12 robots at ticks 0, 5, 10, 15, 20, with typed columns.
    t = run.trajectories
    assert len(t) == 12 * 5
    assert list(t.columns[:8]) == ["tick", "time", "id", "type", "x", "y", "z", "yaw"]
    assert t["tick"].dtype == np.int64 and t["x"].dtype == np.float64
    assert t["id"].map(type).eq(str).all() and t["type"].eq("marxbot").all()
    assert list(t[t["tick"] == 0]["id"]) == [f"mb{i}" for i in range(12)]
    # The last record holds the poses a Simulation with the same seed ends with.
    sim = colony.Simulation(DIFFUSION, seed=2, threads=1,
                            set={"arena.distribute.entity.quantity": 12,
                                 "framework.experiment.length": 2})
    sim.run()
    last = t[t["tick"] == 20]
    np.testing.assert_array_equal(last[["x", "y", "z"]].to_numpy(), sim.robots.positions)
    assert run.hashes is None


def test_load_run_refuses_what_is_not_a_run(tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        colony.results.load_run(tmp_path / "nothing")
    with pytest.raises(FileNotFoundError, match="no experiment.xml"):
        colony.results.load_run(tmp_path)


def test_load_sweep_rows_dtypes_and_long_time_series(tmp_path):
    folder = tmp_path / "sweep"
    subprocess.run([colony_program(), "sweep", DIFFUSION, "--quiet", "--jobs", "2",
                    "--param", "arena.distribute.entity.quantity=5,10",
                    "--param", "controllers.diffusion[dc].params.velocity=0.05,0.1",
                    "--param", "framework.experiment.length=1",
                    "--seeds", "1..2", "--out", str(folder)], check=True)
    sweep = colony.results.load_sweep(folder)
    quantity, velocity = "arena.distribute.entity.quantity", "controllers.diffusion[dc].params.velocity"
    assert sweep.params == [quantity, velocity, "framework.experiment.length"]
    r = sweep.results
    assert len(r) == 2 * 2 * 2
    assert r["run"].map(type).eq(str).all()
    assert r[quantity].dtype == np.int64 and sorted(set(r[quantity])) == [5, 10]
    assert r[velocity].dtype == np.float64 and sorted(set(r[velocity])) == [0.05, 0.1]
    assert r["framework.experiment.length"].dtype == np.int64
    assert r["seed"].dtype == np.int64 and sorted(set(r["seed"])) == [1, 2]
    assert (r["status"] == "ok").all() and r["stale"].dtype == bool and not r["stale"].any()
    assert r["final_state_hash"].map(type).eq(str).all()
    assert r["final_state_hash"].str.fullmatch("[0-9a-f]{16}").all()
    assert r["code"].map(type).eq(str).all()
    assert r["ticks"].dtype == np.int64 and (r["ticks"] == 10).all()
    assert r["mean_displacement"].dtype == np.float64
    # "robots" is a summary column, so the loop functions' metric is metrics.robots.
    assert (r["robots"] == r[quantity]).all() and (r["metrics.robots"] == r[quantity]).all()
    # Each row's final metric is its run's summary.json's.
    for _, row in r.iterrows():
        summary = json.loads((folder / "runs" / row["run"] / "summary.json").read_text())
        assert row["mean_displacement"] == pytest.approx(summary["metrics"]["mean_displacement"],
                                                         rel=1e-12)
        assert row["final_state_hash"] == summary["final_state_hash"]
    # Long form: every run x tick x metric, with the run's parameters and seed.
    ts = sweep.timeseries
    assert list(ts.columns) == ["run", quantity, velocity, "framework.experiment.length", "seed",
                                "tick", "time", "metric", "value"]
    metrics = sorted(set(ts["metric"]))
    assert "mean_displacement" in metrics
    assert len(ts) == len(r) * 2 * len(metrics)  # rows at ticks 0 and 10
    assert ts["tick"].dtype == np.int64 and ts["value"].dtype == np.float64
    assert ts[quantity].dtype == np.int64 and ts["seed"].dtype == np.int64
    one = r.iloc[3]
    final = ts[(ts["run"] == one["run"]) & (ts["tick"] == 10) & (ts["metric"] == "mean_displacement")]
    # (metrics.csv holds fewer digits than results.csv.)
    assert final["value"].tolist() == [pytest.approx(one["mean_displacement"], rel=1e-9)]
    assert final[quantity].tolist() == [one[quantity]]
    # A run of the sweep loads as a run.
    assert sweep.run(one["run"]).summary["seed"] == one["seed"]
    assert isinstance(sweep.run(one["run"]).metrics, pd.DataFrame)


def test_load_sweep_refuses_what_is_not_a_sweep(tmp_path):
    with pytest.raises(FileNotFoundError, match="no sweep.xml"):
        colony.results.load_sweep(tmp_path)
