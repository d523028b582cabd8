"""colony.Simulation: load, step, run, reset, state as arrays, determinism against `colony run`."""

import math
import pathlib
import threading

import numpy as np
import pandas as pd
import pytest

import colony
from conftest import DIFFUSION, colony_run

# 50 robots for 2 s (20 ticks): small and quick, with robots meeting walls and each other.
SMALL = {"arena.distribute.entity.quantity": 50, "framework.experiment.length": 2}


def small(seed=3, threads=2):
    return colony.Simulation(DIFFUSION, seed=seed, threads=threads, set=SMALL)


def test_load_step_run_to_the_end():
    sim = small()
    assert (sim.tick, sim.done, sim.seed, sim.threads, sim.length) == (0, False, 3, 2, 20)
    assert len(sim.robots) == sim.robot_count == 50
    sim.step()
    assert sim.tick == 1 and sim.time == pytest.approx(0.1)
    assert sim.run(5) == 5 and sim.tick == 6
    assert sim.run() == 14 and sim.tick == 20 and sim.done
    assert sim.run(10) == 0 and sim.tick == 20  # run stops at the end
    # The diffusion_metrics loop functions' metrics, as a dict of floats.
    metrics = sim.metrics
    assert metrics["robots"] == 50
    assert metrics["mean_displacement"] > 0


def test_reset_equals_a_fresh_load_with_that_seed():
    sim = small(seed=3)
    sim.run()
    sim.reset(seed=8)
    fresh = small(seed=8)
    assert sim.tick == 0 and not sim.done and sim.seed == 8
    assert sim.state_hash() == fresh.state_hash()
    sim.run()
    fresh.run()
    assert sim.state_hash() == fresh.state_hash()
    assert sim.metrics == fresh.metrics
    # No seed: the seed it has, so the same run again.
    end = sim.state_hash()
    sim.reset()
    sim.run()
    assert sim.seed == 8 and sim.state_hash() == end


def test_same_seed_same_hash_whatever_the_threads_and_as_colony_run(tmp_path):
    hashes = {}
    for threads in (1, 2):
        sim = small(seed=5, threads=threads)
        sim.run()
        hashes[threads] = sim.state_hash()
    assert hashes[1] == hashes[2]
    assert len(hashes[1]) == 16 and int(hashes[1], 16) >= 0
    sets = [a for k, v in SMALL.items() for a in ("--set", f"{k}={v}")]
    printed, _ = colony_run([DIFFUSION, "--seed", "5", "--threads", "2", *sets,
                             "--out", str(tmp_path / "run")])
    assert printed == hashes[1]
    # A different seed gives a different run.
    other = small(seed=6)
    other.run()
    assert other.state_hash() != hashes[1]


def test_robot_arrays_match_colony_runs_trajectories(tmp_path):
    sim = small(seed=4, threads=2)
    sim.run()
    ids, positions, yaw = sim.robots.ids, sim.robots.positions, sim.robots.yaw
    assert ids == [f"mb{i}" for i in range(50)]
    assert sim.robots.types == ["marxbot"] * 50
    assert positions.shape == (50, 3) and positions.dtype == np.float64
    assert yaw.shape == (50,) and yaw.dtype == np.float64
    q = sim.robots.orientations
    assert q.shape == (50, 4)
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0)
    # The same robots' poses as C++ writes them into trajectories.csv at the last tick.
    colony_run([DIFFUSION, "--seed", "4", "--threads", "2",
                *[a for k, v in SMALL.items() for a in ("--set", f"{k}={v}")],
                "--set", "output.trajectories_every=20", "--out", str(tmp_path / "run")])
    table = pd.read_csv(tmp_path / "run" / "trajectories.csv", float_precision="round_trip")
    last = table[table["tick"] == 20]
    assert list(last["id"]) == ids
    np.testing.assert_array_equal(last[["x", "y", "z"]].to_numpy(), positions)
    np.testing.assert_array_equal(last["yaw"].to_numpy(), yaw)
    # Copies: stepping on does not change an array already read.
    before = positions.copy()
    sim.reset()
    sim.run(3)
    np.testing.assert_array_equal(positions, before)


EXPERIMENT = """<?xml version="1.0"?>
<colony>
  <framework>
    <experiment length="10" ticks_per_second="10" random_seed="1"/>
  </framework>
  <controllers>
    <diffusion id="dc" library="diffusion">
      <actuators><differential_steering/></actuators>
      <sensors><proximity/><positioning/><wheel_encoders/></sensors>
      <params velocity="0.05"/>
    </diffusion>
  </controllers>
  <arena size="4,4,1" center="0,0,0.5">
    <box id="wall" size="0.1,2,0.4"><body position="0.2,0,0"/></box>
    <marxbot id="near"><body position="0,0,0"/><controller config="dc"/></marxbot>
    <marxbot id="far"><body position="-1.5,1.5,0" orientation="90,0,0"/><controller config="dc"/></marxbot>
  </arena>
  <physics_engines><kinematics2d id="k2d"/></physics_engines>
</colony>
"""


def test_sensor_arrays(tmp_path):
    path = tmp_path / "facing_a_box.xml"
    path.write_text(EXPERIMENT)
    sim = colony.Simulation(path, threads=1)
    assert set(sim.sensors) == {"proximity", "positioning", "wheel_encoders"}
    sim.run(2)  # the controllers' first commands are applied at the second tick
    prox = sim.sensors["proximity"]
    assert prox.ids == ["near", "far"] and list(prox.robot_index) == [0, 1]
    assert prox.values.shape == (2, 24) and prox.angles.shape == (2, 24)
    # 24 sensors 15 degrees apart from 7.5 degrees: the front two flank 0.
    np.testing.assert_allclose(np.sort(np.abs(prox.angles[0]))[:2], math.radians(7.5), atol=1e-6)
    assert np.all((prox.values >= 0) & (prox.values <= 1))
    # The box 0.15 m ahead of the first robot's centre is seen by the sensors facing it, by
    # none facing away.
    ahead = np.cos(prox.angles[0])
    assert prox.values[0][ahead > 0.9].min() > 0
    assert np.all(prox.values[0][ahead < 0] == 0)
    assert np.all(prox.values[1] == 0)  # nothing near the other robot
    # The positioning sensor reads what sim.robots holds (no noise), row for row.
    pos = sim.sensors["positioning"]
    assert pos.columns == ["x", "y", "z", "yaw"] and pos.values.shape == (2, 4)
    np.testing.assert_allclose(pos.values[:, :3], sim.robots.positions, atol=1e-12)
    np.testing.assert_allclose(pos.values[:, 3], sim.robots.yaw, atol=1e-12)
    enc = sim.sensors["wheel_encoders"]
    assert enc.values.shape == (2, 2)
    # The free robot drives straight at 0.05 m/s: 5 mm per wheel in a tick.
    np.testing.assert_allclose(enc.values[1], [0.005, 0.005], atol=1e-6)
    with pytest.raises(KeyError, match="no robot carries a sensor 'camera'.*proximity"):
        sim.sensors["camera"]


def test_run_releases_the_gil_and_refuses_a_second_caller():
    sim = colony.Simulation(DIFFUSION, seed=1, threads=2,
                            set={"arena.distribute.entity.quantity": 300,
                                 "framework.experiment.length": 1000})
    worker = threading.Thread(target=sim.run, args=(2000,))
    worker.start()
    # This thread runs Python while the other steps: the GIL is released.
    while sim.tick == 0 and worker.is_alive():
        pass
    assert worker.is_alive()
    with pytest.raises(RuntimeError, match="in use by another Python thread"):
        sim.step()
    worker.join()
    assert sim.tick == 2000


def test_set_controller_param_takes_effect_at_reset():
    sim = small(seed=2)
    sim.run()
    before = sim.metrics["mean_displacement"]
    sim.set_controller_param("dc", "velocity", 0.0)
    sim.reset()
    sim.run()
    assert sim.metrics["mean_displacement"] == 0.0 < before


def test_a_path_like_file_and_repr():
    sim = colony.Simulation(pathlib.Path(DIFFUSION).resolve(), seed=1, threads=0, set=SMALL)
    assert sim.threads == 1
    assert "50 robots" in repr(sim) and "tick 0" in repr(sim)
