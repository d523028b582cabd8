"""Errors: the simulator's become colony.ConfigError or colony.RuntimeFailure with its message;
bad arguments become TypeError or ValueError, never a crash."""

import os

import pytest

import colony
from conftest import DIFFUSION

SMALL = {"arena.distribute.entity.quantity": 10, "framework.experiment.length": 1}


def test_the_exception_classes():
    assert issubclass(colony.ConfigError, colony.Error)
    assert issubclass(colony.RuntimeFailure, colony.Error)
    assert not issubclass(colony.ConfigError, colony.RuntimeFailure)
    assert issubclass(colony.Error, RuntimeError)


def test_a_missing_file_names_its_path(tmp_path):
    missing = str(tmp_path / "no_such_experiment.xml")
    with pytest.raises(colony.ConfigError, match="no_such_experiment.xml") as info:
        colony.Simulation(missing)
    assert missing in str(info.value)


def test_a_malformed_experiment_names_file_line_element_and_attribute(tmp_path):
    path = tmp_path / "bad.xml"
    with open(DIFFUSION) as f:
        lines = f.read().split("\n")
    line = next(i for i, text in enumerate(lines) if "<experiment " in text)
    lines[line] = lines[line].replace('length="60"', 'length="sixty"')
    path.write_text("\n".join(lines))
    with pytest.raises(colony.ConfigError) as info:
        colony.Simulation(path)
    message = str(info.value)
    assert f"{path}:{line + 1}: <experiment> attribute 'length'" in message
    assert "sixty" in message


def test_xml_that_does_not_parse(tmp_path):
    path = tmp_path / "broken.xml"
    path.write_text("<colony>\n  <framework>\n</colony>\n")
    with pytest.raises(colony.ConfigError, match="broken.xml"):
        colony.Simulation(path)


def test_a_bad_set_path_or_value():
    with pytest.raises(colony.ConfigError, match="attribute 'lenght'"):
        colony.Simulation(DIFFUSION, set={"framework.experiment.lenght": 5})
    with pytest.raises(colony.ConfigError, match="quantity"):
        colony.Simulation(DIFFUSION, set={"arena.distribute.entity.quantity": -3})


@pytest.mark.parametrize("kwargs, error", [
    ({"seed": "seven"}, TypeError),
    ({"seed": -1}, TypeError),
    ({"seed": 1.5}, TypeError),
    ({"threads": "two"}, TypeError),
    ({"threads": -1}, ValueError),
    ({"threads": 10**6}, ValueError),
    ({"set": ["framework.experiment.length=5"]}, TypeError),
    ({"set": {"framework.experiment.length": [5]}}, TypeError),
    ({"set": {"framework.experiment.length": None}}, TypeError),
    ({"set": {5: 5}}, TypeError),
])
def test_bad_argument_types(kwargs, error):
    with pytest.raises(error):
        colony.Simulation(DIFFUSION, **kwargs)


def test_bad_file_arguments():
    with pytest.raises(TypeError):
        colony.Simulation(None)
    with pytest.raises(TypeError):
        colony.Simulation(42)
    with pytest.raises(TypeError):
        colony.Simulation(DIFFUSION, 3)  # seed is keyword-only


def test_bad_calls_on_a_simulation():
    sim = colony.Simulation(DIFFUSION, seed=1, set=SMALL)
    with pytest.raises(ValueError, match="ticks must be >= 0"):
        sim.run(-1)
    with pytest.raises(TypeError):
        sim.run("ten")
    with pytest.raises(TypeError):
        sim.reset(seed=-5)
    with pytest.raises(TypeError):
        sim.sensors[0]
    with pytest.raises(ValueError, match="dc"):
        sim.set_controller_param("no_such_controller", "velocity", 0.1)
    with pytest.raises(TypeError):
        sim.set_controller_param("dc", "velocity", [0.1])
    # A misspelt parameter is reported by the next reset, as a load would.
    sim.set_controller_param("dc", "velocty", 0.1)
    with pytest.raises(colony.ConfigError, match="velocity"):
        sim.reset()
    # Then the simulation is empty, and says so, until a reset succeeds.
    with pytest.raises(colony.RuntimeFailure, match="last Reset failed"):
        sim.step()


def test_a_controller_that_throws_is_a_runtime_failure(tmp_path):
    plugin = os.path.join(os.environ["COLONY_TEST_PLUGIN_DIR"], "libsweep_misbehave.so")
    assert os.path.exists(plugin), plugin
    path = tmp_path / "throws.xml"
    path.write_text(f"""<colony>
  <framework><experiment length="5" ticks_per_second="10"/></framework>
  <controllers>
    <sweep_misbehave id="m" library="{plugin}"><params mode="throw_int" at="3"/></sweep_misbehave>
  </controllers>
  <arena size="2,2,1"><marxbot id="bot"><body position="0,0,0"/><controller config="m"/></marxbot></arena>
  <physics_engines><kinematics2d id="k"/></physics_engines>
</colony>
""")
    sim = colony.Simulation(path)
    sim.run(2)
    with pytest.raises(colony.RuntimeFailure, match="bot") as info:
        sim.run()
    assert "sweep_misbehave" in str(info.value)
    assert not isinstance(info.value, colony.ConfigError)
    # The simulation can be reset and run again after a failure.
    sim.reset()
    assert sim.tick == 0
    sim.run(2)
    assert sim.tick == 2
