"""Colony from Python: drive simulations, read their state as numpy arrays, load results.

    import colony
    sim = colony.Simulation("experiments/diffusion.xml", seed=3, threads=2,
                            set={"arena.distribute.entity.quantity": 500})
    sim.run(100)
    sim.robots.positions          # N x 3 (m)
    sim.sensors["proximity"].values   # N x 24
    sim.state_hash()              # as `colony run` prints it

colony.results loads run and sweep folders into pandas. docs/python.md is the guide.
"""

import os as _os

from . import _paths

# Plugins (controllers, loop functions) named without a path are looked for in
# $COLONY_PLUGIN_PATH first: the build tree's plugin folder is added after
# what the user set, so `import colony` from the build tree finds them.
if _paths.PLUGIN_DIR and _os.path.isdir(_paths.PLUGIN_DIR):
    _user = _os.environ.get("COLONY_PLUGIN_PATH", "")
    if _paths.PLUGIN_DIR not in _user.split(":"):
        _os.environ["COLONY_PLUGIN_PATH"] = (
            _user + ":" + _paths.PLUGIN_DIR if _user else _paths.PLUGIN_DIR
        )

from . import _colony  # noqa: E402
from ._colony import ConfigError, Error, RuntimeFailure, SensorReadings  # noqa: E402

from . import results  # noqa: E402  (pandas is imported when a table is first read)

for _cls in (Error, ConfigError, RuntimeFailure, SensorReadings):
    _cls.__module__ = "colony"  # colony.ConfigError in tracebacks, not colony._colony.ConfigError

__all__ = ["Simulation", "Robots", "Sensors", "SensorReadings", "Actuators", "ActuatorCommands", "Error", "ConfigError",
           "RuntimeFailure", "results"]


class Robots:
    """The robots alive now (entities carrying a controller), in the order of their slots in the
    space (the file's order for the file's robots), as the trajectories table lists them. Each
    attribute is a fresh copy, made when read."""

    def __init__(self, sim):
        self._sim = sim

    @property
    def ids(self):
        """list of str"""
        return self._sim._robot_ids()

    @property
    def types(self):
        """list of str: each robot's entity type (marxbot, handbot, eyebot)"""
        return self._sim._robot_types()

    @property
    def positions(self):
        """float64 array, N x 3: x, y, z (m), world frame, the centre of the robot's base"""
        return self._sim._positions()

    @property
    def yaw(self):
        """float64 array, N: rad, in (-pi, pi], about z"""
        return self._sim._yaw()

    @property
    def orientations(self):
        """float64 array, N x 4: unit quaternions (w, x, y, z)"""
        return self._sim._orientations()

    def __len__(self):
        return self._sim.robot_count

    def __repr__(self):
        return f"<colony.Robots: {len(self)} robots>"


class Sensors:
    """The sensors robots carry, by registered name or element name (`proximity`,
    `footbot_proximity`): sensors[name] copies every carrying robot's readings into arrays."""

    def __init__(self, sim):
        self._sim = sim

    def __getitem__(self, name):
        if not isinstance(name, str):
            raise TypeError(f"sensor names are str, not {type(name).__name__}")
        return self._sim._sensor(name)

    def __contains__(self, name):
        return name in self._sim._sensor_names()

    def __iter__(self):
        return iter(self._sim._sensor_names())

    def __len__(self):
        return len(self._sim._sensor_names())

    def keys(self):
        return self._sim._sensor_names()

    def __repr__(self):
        return f"<colony.Sensors: {', '.join(self.keys())}>"


class ActuatorCommands:
    """One actuator of every robot whose controller is an <external_controller> and that carries
    it, in sim.robots order (`ids`, `robot_index`). set() writes commands that the next tick's
    act phase applies, as a C++ controller's calls would; get() reads them back."""

    def __init__(self, sim, name):
        self._sim = sim
        self.name = name
        self.ids, self.robot_index = sim._actuator_robots(name)

    def set(self, *command):
        """differential_steering: set(left, right), each a number or one float per robot (m/s),
        or set(array N x 2). leds: set(colours), 0..255 integers, shape (3,), (N, 3) or (N, K, 3).
        Wrong shapes raise ValueError, values that are not finite numbers ValueError naming the
        robot; a wheel speed beyond the wheels' limit runs at the limit with a warning once per
        robot, as for a C++ controller."""
        if len(command) == 1:
            command = command[0]
        self._sim._set_actuator(self.name, command)

    def get(self):
        """The commands the actuators hold: differential_steering N x 2 (left, right m/s), leds
        N x K x 3 uint8."""
        return self._sim._get_actuator(self.name)

    def __len__(self):
        return len(self.ids)

    def __repr__(self):
        return f"<colony.ActuatorCommands '{self.name}' of {len(self)} robots>"


class Actuators:
    """The actuators Python sets: those of robots whose controller is an <external_controller>,
    by registered name or element name (`differential_steering`, `leds`)."""

    def __init__(self, sim):
        self._sim = sim

    def __getitem__(self, name):
        if not isinstance(name, str):
            raise TypeError(f"actuator names are str, not {type(name).__name__}")
        return ActuatorCommands(self._sim, name)

    def __contains__(self, name):
        return name in self._sim._actuator_names()

    def __iter__(self):
        return iter(self._sim._actuator_names())

    def __len__(self):
        return len(self._sim._actuator_names())

    def keys(self):
        return self._sim._actuator_names()

    def __repr__(self):
        return f"<colony.Actuators: {', '.join(self.keys())}>"


class Simulation(_colony.Simulation):
    """An experiment loaded from an XML file, stepped from Python.

    Simulation(file, *, seed=None, threads=None, set=None): `seed` replaces <experiment
    random_seed>, `threads` <system threads> (0 or 1: the calling thread only), `set` is a dict of
    overrides as `colony run --set PATH=VALUE` takes them ({"framework.experiment.length": 10}).
    Raises ConfigError (bad file, path or value: the message names the file, line, element and
    attribute), TypeError or ValueError (bad arguments)."""

    def __init__(self, file, *, seed=None, threads=None, set=None):
        if set is not None and not isinstance(set, dict):
            raise TypeError(f"set must be a dict of path: value, not {type(set).__name__}")
        super().__init__(_os.fspath(file), seed=seed, threads=threads, set=set)

    @property
    def robots(self):
        return Robots(self)

    @property
    def sensors(self):
        return Sensors(self)

    @property
    def actuators(self):
        return Actuators(self)

    def __repr__(self):
        return (f"<colony.Simulation {self.file!r}: {self.robot_count} robots, tick {self.tick}"
                f"{' (done)' if self.done else ''}, seed {self.seed}>")

