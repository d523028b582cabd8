"""Robots driven from Python: <external_controller> with sim.actuators, and batched Python
controllers (<python_batch_controller>) from colony.Simulation and from `colony run`."""

import math
import re
import subprocess
import textwrap

import numpy as np
import pytest

import colony
from conftest import colony_program, colony_run

BATCHED = "examples/python/batched_diffusion.xml"


def experiment(tmp_path, controller, robots=12, length=2, name="exp.xml", extra=""):
    """Writes an experiment with `robots` marXbots in a walled 3 x 3 m arena, each running the
    controller configuration `controller` (its id must be "c"), and returns its path."""
    xml = f"""<?xml version="1.0"?>
<colony>
  <framework>
    <system threads="2"/>
    <experiment length="{length}" ticks_per_second="10" random_seed="4"/>
  </framework>
  <controllers>
{textwrap.indent(textwrap.dedent(controller).strip(), "    ")}
  </controllers>
  <arena size="3,3,1" center="0,0,0.5">
    <walls thickness="0.1" height="0.5"/>
    {extra}
    <distribute>
      <position method="uniform" min="-1.3,-1.3,0" max="1.3,1.3,0"/>
      <orientation method="uniform" min="0,0,0" max="360,0,0"/>
      <entity quantity="{robots}" max_trials="100">
        <marxbot id="mb"><controller config="c"/></marxbot>
      </entity>
    </distribute>
  </arena>
  <physics_engines><kinematics2d id="k2d"/></physics_engines>
</colony>
"""
    path = tmp_path / name
    path.write_text(xml)
    return path


EXTERNAL = """
<external_controller id="c">
  <actuators><differential_steering/><leds/></actuators>
  <sensors><proximity/><positioning/></sensors>
</external_controller>
"""

CPP_DIFFUSION = """
<diffusion id="c" library="diffusion">
  <actuators><differential_steering/></actuators>
  <sensors><proximity/></sensors>
  <params alpha="7.5" delta="0.1" velocity="0.05"/>
</diffusion>
"""


def batch(module, cls="Controller", params=""):
    return f"""
<python_batch_controller id="c">
  <actuators><differential_steering/></actuators>
  <sensors><proximity/></sensors>
  <params module="{module}" class="{cls}" {params}/>
</python_batch_controller>
"""


# --- external controllers -------------------------------------------------------------------------

def test_external_wheels_drive_the_robots(tmp_path):
    sim = colony.Simulation(experiment(tmp_path, EXTERNAL, robots=4), threads=1)
    wheels = sim.actuators["differential_steering"]
    assert wheels.ids == sim.robots.ids and list(wheels.robot_index) == [0, 1, 2, 3]
    assert list(sim.actuators) == ["differential_steering", "leds"]
    start, yaw = sim.robots.positions, sim.robots.yaw
    # Robot 0 forwards at 0.1 m/s, robot 1 backwards, robot 2 turns on the spot, robot 3 stays.
    wheels.set(np.array([0.1, -0.1, -0.05, 0.0]), np.array([0.1, -0.1, 0.05, 0.0]))
    np.testing.assert_array_equal(wheels.get(), [[0.1, 0.1], [-0.1, -0.1], [-0.05, 0.05], [0, 0]])
    sim.run(5)
    moved = sim.robots.positions - start
    heading = np.stack([np.cos(yaw), np.sin(yaw)], axis=1)
    along = (moved[:, :2] * heading).sum(1)
    # 0.5 s at 0.1 m/s (the wheels reach it in the first tick: max_acceleration 3 m/s^2).
    assert along[0] == pytest.approx(0.05, rel=1e-6)
    assert along[1] == pytest.approx(-0.05, rel=1e-6)
    assert np.hypot(*moved[2, :2]) < 1e-9 and sim.robots.yaw[2] != pytest.approx(yaw[2])
    assert np.all(moved[3] == 0)
    # The commands hold until set again; one number is every robot's.
    wheels.set(0.0, 0.0)
    np.testing.assert_array_equal(wheels.get(), np.zeros((4, 2)))
    # An N x 2 array works too.
    wheels.set(np.full((4, 2), 0.02))
    np.testing.assert_array_equal(wheels.get(), np.full((4, 2), 0.02))


def test_external_matches_the_cpp_controller_tick_for_tick(tmp_path):
    """Diffusion computed in numpy from sim.sensors and set through sim.actuators moves the robots
    exactly as the C++ diffusion controller does (the same sums in the same order)."""
    cpp = colony.Simulation(experiment(tmp_path, CPP_DIFFUSION, robots=20, name="cpp.xml"))
    # The same devices, and the same number of lines (<distribute> seeds by its line).
    ext = colony.Simulation(experiment(tmp_path, """
        <external_controller id="c">
          <actuators><differential_steering/></actuators>
          <sensors><proximity/></sensors>
          <!-- no params -->
        </external_controller>""", robots=20, name="ext.xml"))
    assert cpp.state_hash() == ext.state_hash()
    wheels = ext.actuators["differential_steering"]
    angles = ext.sensors["proximity"].angles[0]
    # As the controller computes: float readings times float cosines, summed in double.
    cos = np.cos(angles).astype(np.float32)
    sin = np.sin(angles).astype(np.float32)
    alpha, delta, v = 7.5 * math.pi / 180, 0.1, 0.05
    for _ in range(20):
        cpp.step()
        ext.step()
        values = ext.sensors["proximity"].values.astype(np.float32)
        x = np.zeros(len(values))
        y = np.zeros(len(values))
        for k in range(values.shape[1]):
            x += (values[:, k] * cos[k]).astype(np.float64)
            y += (values[:, k] * sin[k]).astype(np.float64)
        x /= values.shape[1]
        y /= values.shape[1]
        angle = np.arctan2(y, x)
        straight = ((np.abs(angle) <= alpha) & (np.hypot(x, y) < delta)) | (np.abs(angle) > math.pi / 2)
        wheels.set(np.where(straight | (angle > 0), v, -v), np.where(straight | (angle <= 0), v, -v))
        np.testing.assert_array_equal(cpp.robots.positions, ext.robots.positions)
    assert cpp.state_hash() == ext.state_hash()
    assert np.abs(cpp.robots.positions - experiment_start(tmp_path)).max() > 0.05


def experiment_start(tmp_path):
    return colony.Simulation(tmp_path / "cpp.xml").robots.positions


def test_external_leds(tmp_path):
    sim = colony.Simulation(experiment(tmp_path, EXTERNAL, robots=3), threads=1)
    leds = sim.actuators["leds"]
    leds.set([255, 0, 0])
    colours = leds.get()
    assert colours.shape[0] == 3 and colours.shape[2] == 3 and colours.dtype == np.uint8
    assert (colours == [255, 0, 0]).all()
    leds.set(np.array([[0, 0, 255], [0, 255, 0], [9, 9, 9]]))
    assert (leds.get()[1] == [0, 255, 0]).all()
    with pytest.raises(ValueError, match="not an integer from 0 to 255"):
        leds.set(np.array([[0, 0, 256], [0, 0, 0], [0, 0, 0]]))


def test_external_bad_commands(tmp_path, capfd):
    sim = colony.Simulation(experiment(tmp_path, EXTERNAL, robots=4), threads=1)
    wheels = sim.actuators["differential_steering"]
    with pytest.raises(ValueError, match=r"expected 4 numbers \(one per robot\) or one number, "
                                         r"not an array of shape \(3,\)"):
        wheels.set(np.zeros(3), np.zeros(4))
    with pytest.raises(ValueError, match="nan for robot 'mb2' .row 2. is not a finite number"):
        wheels.set(np.array([0, 0, math.nan, 0]), np.zeros(4))
    with pytest.raises(TypeError, match="expected a number or an array of 4 numbers"):
        wheels.set("fast", 0)
    with pytest.raises(ValueError, match=r"shape \(4, 2\), not an array of shape \(4, 3\)"):
        wheels.set(np.zeros((4, 3)))
    np.testing.assert_array_equal(wheels.get(), np.zeros((4, 2)))  # nothing was written
    # Beyond the wheels' limit (marXbot: 0.3 m/s): as for a C++ controller, the wheel runs at the
    # limit and the simulator says so, once per robot.
    wheels.set(1.0, 1.0)
    start = sim.robots.positions
    sim.run(10)
    assert np.hypot(*(sim.robots.positions - start)[:, :2].T).max() <= 0.3 + 1e-9
    err = capfd.readouterr().err
    assert "differential_steering wheel speed 1 m/s is beyond the wheels' limit, 0.3 m/s" in err
    with pytest.raises(KeyError, match="actuators Python can set: differential_steering, leds"):
        sim.actuators["gripper"]


def test_actuators_of_robots_with_their_own_controller_are_refused(tmp_path):
    sim = colony.Simulation(experiment(tmp_path, CPP_DIFFUSION, robots=3))
    with pytest.raises(KeyError, match="carried only by robots whose controllers set it themselves "
                                       r"\(robot 'mb0' runs <diffusion>\)"):
        sim.actuators["differential_steering"]
    assert list(sim.actuators) == []


# --- batched Python controllers -------------------------------------------------------------------

def test_batched_diffusion_same_hash_at_0_1_2_threads_and_as_colony_run():
    hashes = set()
    for threads in (0, 1, 2):
        sim = colony.Simulation(BATCHED, threads=threads, set={"framework.experiment.length": 3})
        sim.run()
        assert sim.tick == 30
        hashes.add(sim.state_hash())
    assert len(hashes) == 1
    final, _ = colony_run([BATCHED, "--threads", "2", "--set", "framework.experiment.length=3"])
    assert {final} == hashes


def test_batched_diffusion_avoids_walls_and_moves(tmp_path):
    sim = colony.Simulation(BATCHED, set={"framework.experiment.length": 20})
    start = sim.robots.positions
    sim.run()
    assert sim.metrics["mean_displacement"] > 0.3
    assert np.abs(sim.robots.positions[:, :2]).max() < 3.95   # inside the 8 x 8 m walls
    assert not np.allclose(start, sim.robots.positions)
    # Reset builds a new Python object: the same run again.
    end = sim.state_hash()
    sim.reset()
    sim.run()
    assert sim.state_hash() == end


def test_batched_readings_and_params_reach_the_class(tmp_path):
    (tmp_path / "probe.py").write_text(textwrap.dedent("""
        import numpy as np
        seen = []
        class Controller:
            def __init__(self, params):
                seen.append(("params", params))
            def step(self, readings):
                seen.append(("step", {k: (v.shape, v.dtype.name) for k, v in readings.items()}))
                n = readings["proximity"].shape[0]
                return {"differential_steering": (np.full(n, 0.1), 0.1)}
        """))
    sim = colony.Simulation(experiment(tmp_path, batch("probe", params='v="0.5" n="3" on="true" '
                                                                      'name="x"'), robots=5))
    sim.step()
    import probe
    assert probe.seen[0] == ("params", {"v": 0.5, "n": 3, "on": True, "name": "x"})
    assert probe.seen[1] == ("step", {"proximity": ((5, 24), "float64"),
                                      "proximity_angles": ((5, 24), "float64")})
    start = sim.robots.positions
    sim.run(2)   # the commands of tick 1 drive ticks 2 and 3 forwards at 0.1 m/s
    assert np.hypot(*(sim.robots.positions - start)[:, :2].T) == pytest.approx(np.full(5, 0.02))


def write_module(tmp_path, name, body):
    (tmp_path / f"{name}.py").write_text(textwrap.dedent(body))


def test_a_python_exception_stops_the_run_with_its_traceback(tmp_path):
    write_module(tmp_path, "crash", """
        import numpy as np
        class Controller:
            def __init__(self, params):
                self.ticks = 0
            def step(self, readings):
                self.ticks += 1
                if self.ticks == 3:
                    return self.helper()
                return None
            def helper(self):
                return 1 / 0
        """)
    path = experiment(tmp_path, batch("crash"), robots=3)
    sim = colony.Simulation(path)
    sim.run(2)
    with pytest.raises(colony.RuntimeFailure) as e:
        sim.step()
    message = str(e.value)
    assert re.search(r"exp\.xml:\d+: controller 'python_batch_controller' \(configuration 'c', "
                     r"stepping its 3 robots together\) failed at tick 3: Python error in "
                     r"Controller\.step\(\) \(.*crash\.py\)", message), message
    assert "Traceback (most recent call last)" in message
    assert re.search(r'crash\.py", line 9, in step', message), message
    assert re.search(r'crash\.py", line 12, in helper', message), message
    assert "ZeroDivisionError: division by zero" in message
    # The same from `colony run`: exit status 1, the message on stderr.
    out = subprocess.run([colony_program(), "run", str(path), "--quiet"], capture_output=True,
                         text=True)
    assert out.returncode == 1
    assert "ZeroDivisionError: division by zero" in out.stderr
    assert 'crash.py", line 12, in helper' in out.stderr


@pytest.mark.parametrize("returned, expected", [
    ('[1, 2]', r"returned a list; it returns a dict of actuator name to commands"),
    ('{"wheels": (0, 0)}', r"returned commands for 'wheels', which is not among the controller's "
                           r"<actuators> \(differential_steering\)"),
    ('{"differential_steering": (np.zeros(2), 0)}',
     r"returned bad commands: differential_steering left: expected 3 numbers \(one per robot\) or "
     r"one number, not an array of shape \(2,\)"),
    ('{"differential_steering": (0, 0, 0)}',
     r"returned bad commands: differential_steering: expected \(left, right\), not a tuple of 3"),
    ('{"differential_steering": "go"}',
     r"returned bad commands: differential_steering: expected \(left, right\) or an N x 2 array, "
     r"not str"),
    ('{"differential_steering": (np.array([0, np.inf, 0]), 0)}',
     r"returned bad commands: differential_steering left: inf for robot 'mb1' \(row 1\) is not "
     r"a finite number"),
    ('{1: 0}', r"returned a key 1 that is not an actuator name"),
])
def test_bad_commands_are_clear_errors(tmp_path, returned, expected):
    # A module is imported once per process: each case has its own.
    name = "bad_" + tmp_path.name.replace("-", "_")
    write_module(tmp_path, name, f"""
        import numpy as np
        class Controller:
            def __init__(self, params):
                pass
            def step(self, readings):
                return {returned}
        """)
    sim = colony.Simulation(experiment(tmp_path, batch(name), robots=3))
    with pytest.raises(colony.RuntimeFailure, match=r"exp\.xml:\d+: .*failed at tick 1: "
                                                    r"Controller\.step\(\) \(.*bad_.*\.py\) " + expected):
        sim.step()


def line_of(path, text):
    return next(i for i, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def test_missing_module_class_and_broken_modules_are_config_errors(tmp_path):
    path = experiment(tmp_path, batch("nowhere"), robots=2, name="nowhere.xml")
    params_line = line_of(path, "<params")
    with pytest.raises(colony.ConfigError) as e:
        colony.Simulation(path)
    assert re.search(rf"nowhere\.xml:{params_line}: <params> attribute 'module': "
                     r"no Python module 'nowhere' \(looked for nowhere\.py in .*"
                     + re.escape(str(tmp_path)), str(e.value)), str(e.value)

    write_module(tmp_path, "some", """
        class Other:
            def step(self, readings):
                return None
        NOT_A_CLASS = 3
        """)
    with pytest.raises(colony.ConfigError, match=rf"exp\.xml:{params_line}: <params> attribute "
                       r"'class': Python module 'some' \(.*some\.py\) has no class "
                       r"'Controller'; its classes: Other"):
        colony.Simulation(experiment(tmp_path, batch("some"), robots=2))
    with pytest.raises(colony.ConfigError, match="'NOT_A_CLASS' in Python module 'some' .* is not "
                                                 "a class"):
        colony.Simulation(experiment(tmp_path, batch("some", "NOT_A_CLASS"), robots=2))

    write_module(tmp_path, "broken", """
        import numpy as np
        def f(:
        """)
    with pytest.raises(colony.ConfigError, match=r"(?s)Python module 'broken' failed to import: .*"
                                                 r"SyntaxError"):
        colony.Simulation(experiment(tmp_path, batch("broken"), robots=2))

    write_module(tmp_path, "nostep", """
        class Controller:
            def __init__(self, params):
                pass
        """)
    with pytest.raises(colony.ConfigError, match="Python class Controller .* has no method step"):
        colony.Simulation(experiment(tmp_path, batch("nostep"), robots=2))

    write_module(tmp_path, "badinit", """
        class Controller:
            def __init__(self, params):
                raise ValueError("gain must be positive, not " + str(params["gain"]))
            def step(self, readings):
                return None
        """)
    with pytest.raises(colony.ConfigError, match=r"(?s)controller 'python_batch_controller' failed "
                       r"to start: Python class Controller .* could not be created: .*ValueError: "
                       r"gain must be positive, not -1"):
        colony.Simulation(experiment(tmp_path, batch("badinit", params='gain="-1"'), robots=2))

    # From `colony run`: exit status 2, the same message.
    out = subprocess.run([colony_program(), "run", str(path), "--quiet"], capture_output=True,
                         text=True)
    assert out.returncode == 2
    assert "no Python module 'nowhere'" in out.stderr and f"nowhere.xml:{params_line}" in out.stderr


def test_missing_module_and_class_parameters(tmp_path):
    path = experiment(tmp_path, """
        <python_batch_controller id="c">
          <actuators><differential_steering/></actuators>
          <params class="C"/>
        </python_batch_controller>""", robots=2)
    with pytest.raises(colony.ConfigError, match=r"exp\.xml:\d+: <params> .*'module'"):
        colony.Simulation(path)


def test_a_sensor_without_an_array_form_is_refused_at_load(tmp_path):
    write_module(tmp_path, "ok", """
        class Controller:
            def __init__(self, params):
                pass
            def step(self, readings):
                return None
        """)
    path = experiment(tmp_path, """
        <python_batch_controller id="c">
          <actuators><differential_steering/></actuators>
          <sensors><range_and_bearing/></sensors>
          <params module="ok" class="Controller"/>
        </python_batch_controller>""", robots=2)
    with pytest.raises(colony.ConfigError, match="sensor 'range_and_bearing' has no array form "
                                                 "for Python controllers"):
        colony.Simulation(path)


# --- per-robot Python controllers -----------------------------------------------------------------

PER_ROBOT_DIFFUSION = """
import math
import numpy as np

log = []

class Diffusion:
    def init(self, params):
        self.alpha = params["alpha"] * math.pi / 180
        self.delta = params["delta"]
        self.velocity = params["velocity"]
        self.cos = self.sin = None
        log.append(("init", self.robot_id))

    def step(self, readings):
        values = readings["proximity"]              # this robot's 24 readings
        if self.cos is None:                        # as the C++ controller keeps them: floats
            self.cos = [np.float32(math.cos(a)) for a in readings["proximity_angles"]]
            self.sin = [np.float32(math.sin(a)) for a in readings["proximity_angles"]]
        x = y = 0.0
        for value, c, s in zip(values.astype(np.float32), self.cos, self.sin):
            x += float(value * c)                   # a float product, summed in double
            y += float(value * s)
        x /= len(values)
        y /= len(values)
        angle = math.atan2(y, x)
        v = self.velocity
        if (abs(angle) <= self.alpha and math.hypot(x, y) < self.delta) or abs(angle) > math.pi / 2:
            return {"differential_steering": (v, v)}
        return {"differential_steering": (v, -v) if angle > 0 else (-v, v)}

    def reset(self):
        log.append(("reset", self.robot_id))
"""


def per_robot(module, cls="Diffusion", params='alpha="7.5" delta="0.1" velocity="0.05"'):
    return f"""
<python_controller id="c">
  <actuators><differential_steering/></actuators>
  <sensors><proximity/></sensors>
  <params module="{module}" class="{cls}" {params}/>
</python_controller>
"""


def test_per_robot_controller_moves_robots_as_the_cpp_controller(tmp_path):
    write_module(tmp_path, "robot_diffusion", PER_ROBOT_DIFFUSION)
    cpp = colony.Simulation(experiment(tmp_path, CPP_DIFFUSION, robots=15, name="cpp.xml"))
    cpp.run()
    hashes = set()
    for threads in (0, 1, 2):
        sim = colony.Simulation(experiment(tmp_path, per_robot("robot_diffusion"), robots=15),
                                threads=threads)
        sim.run()
        hashes.add(sim.state_hash())
    assert hashes == {cpp.state_hash()}
    import robot_diffusion
    assert robot_diffusion.log[:2] == [("init", "mb0"), ("init", "mb1")]
    sim.reset()
    assert robot_diffusion.log[-1] == ("reset", "mb14")
    final, _ = colony_run([str(tmp_path / "exp.xml")])
    assert final == cpp.state_hash()


def test_per_robot_exception_names_the_robot_with_the_traceback(tmp_path):
    write_module(tmp_path, "fails", """
        class Controller:
            def step(self, readings):
                if self.robot_id == "mb1":
                    raise RuntimeError("sensor out of range: " + str(readings["proximity"].shape))
        """)
    sim = colony.Simulation(experiment(tmp_path, per_robot("fails", "Controller", ""), robots=3))
    with pytest.raises(colony.RuntimeFailure, match=r"(?s)failed at tick 1: Python error in "
                       r"Controller\.step\(\) of robot 'mb1' \(.*fails\.py\): .*line 5, in step.*"
                       r"RuntimeError: sensor out of range: \(24,\)"):
        sim.step()
