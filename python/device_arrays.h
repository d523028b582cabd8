// Devices as numpy arrays, shared by the module (colony._colony: sim.sensors,
// sim.actuators) and the batched controller host (python_batch_controller):
// the readings of one sensor for many robots copied into one array, and one
// array of commands written into many robots' actuators.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "core/control_interface.h"

namespace colony::python {

namespace py = pybind11;

// The readings of one sensor for a list of robots, as arrays.
struct SensorArrays {
  py::object values;                 // float64, one row per robot
  py::object angles = py::none();    // ring sensors: each reading's direction (rad), N x K
  std::vector<std::string> columns;  // what the columns of a non-ring sensor hold
};

// The kinds of sensor with an array form, for messages.
extern const char* const kArraySensors;
// The kinds of actuator that take arrays, for messages.
extern const char* const kArrayActuators;

// Copies `sensors` (instances of one registered sensor, one per robot, at
// least one) into arrays; `with_angles`: the ring sensors' angles too.
// Returns false when the sensor has no array form.
bool ReadSensorArrays(const std::vector<Sensor*>& sensors, bool with_angles, SensorArrays& out);

// Writes `command` into `actuators` (instances of one registered actuator,
// one per robot, whose ids are `ids`, at least one), as the actuator's
// control interface would be called by a C++ controller:
//   differential_steering: (left, right), each a number or N numbers (m/s),
//     or an N x 2 array;
//   leds: an N x 3 (every LED of a robot) or N x K x 3 array of 0..255
//     integers (red, green, blue), or one colour (3 numbers) for all.
// `what` names the actuator in messages. Throws py::type_error or
// py::value_error (a wrong shape, a number that is not finite or not in
// range, naming the robot), or returns false when the actuator takes no
// arrays; nothing is written then.
bool WriteActuatorArrays(const std::vector<Actuator*>& actuators,
                         const std::vector<std::string>& ids, const std::string& what,
                         py::handle command);

// The commands `actuators` hold, as WriteActuatorArrays takes them
// (differential_steering: N x 2 m/s; leds: N x K x 3 uint8), or None when
// the actuator takes no arrays.
py::object ReadActuatorArrays(const std::vector<Actuator*>& actuators);

}  // namespace colony::python
