// What the Python controller hosts (python_batch_controller.cpp,
// python_controller.cpp) share: the interpreter, importing the user's
// class, and Python errors as text. Not a public header.
//
// The hosts run inside `colony run` (the interpreter is started here, with
// pybind11's embedding, on first use) and inside Python (colony.Simulation:
// the running interpreter is used; the module releases the GIL while it
// steps, and the hosts take it when they call Python).
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <utility>
#include <vector>

#include "core/control_interface.h"

namespace colony::python {

namespace py = pybind11;

// Starts the interpreter when none runs (`colony run`), leaving the GIL
// released. Call on the thread that loads the simulation.
void EnsureInterpreter();

// Whether Python objects may be released now (false while the interpreter
// shuts down or after it has: they are leaked then).
bool PythonAlive();

// The user's class named by a host's <params>: module="name" (a .py file
// found first in the experiment file's folder and path="folder", relative to
// it, then on sys.path) and class="Name". Throws ParamError naming the
// parameter on a missing module, an import that fails (with its traceback)
// or a missing class. Call with the GIL held.
struct UserClass {
  py::object cls;
  std::string module;  // as given
  std::string name;    // the class's name
  std::string file;    // the module's file, for messages
  // "Name (module 'm', /path/m.py)", for messages.
  std::string Describe() const;
};
UserClass ImportUserClass(const Params& params);

// The <params> other than module, class and path, for the user's class: a
// dict of str to int, float, bool (true/false) or str, as the text reads.
py::dict UserParams(const Params& params);

// The Python exception being handled as text with its traceback (the
// frames of the user's code), for the run's error message.
std::string PythonError(py::error_already_set& e);

// A declared device: its element name and the registered device's name.
struct DeviceName {
  std::string label, name;
};
std::vector<DeviceName> SensorNames(const DeviceTable& devices);
std::vector<DeviceName> ActuatorNames(const DeviceTable& devices);
// Throws std::runtime_error when a declared sensor has no array form.
void CheckArraySensors(const DeviceTable& devices);

// The readings step() gets: for sensor j of `sensors`, readings[label] (and
// [name] if the file used an alias) = the members' readings, one row each,
// and for ring sensors readings[label + "_angles"] = their directions
// (rad), read-only and kept in `angles[j]` (None: read them again). `row`:
// one robot's row (K for rings, a number for one-number sensors) instead of
// a 1 x K array.
py::dict Readings(const std::vector<Controller*>& members, const std::vector<DeviceName>& sensors,
                  std::vector<py::object>& angles, bool row);

// Writes what step() returned (None: nothing; else a dict of actuator label
// or name to commands, device_arrays.h) into the members' actuators.
// `where` names step() in messages. Throws std::runtime_error.
void ApplyCommands(const py::object& commands, const std::vector<Controller*>& members,
                   const std::vector<std::string>& ids, const std::vector<DeviceName>& actuators,
                   const std::string& where);

}  // namespace colony::python
