#include "python/device_arrays.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/leds/leds.h"
#include "sensors/battery/battery.h"
#include "sensors/ground/ground.h"
#include "sensors/imu/imu.h"
#include "sensors/light/light.h"
#include "sensors/positioning/positioning.h"
#include "sensors/proximity/proximity.h"
#include "sensors/wheel_encoders/wheel_encoders.h"

namespace colony::python {
namespace {

using Array = py::array_t<double>;

// A 2-D array of `rows` x `cols` doubles, filled with NaN.
Array NanArray(size_t rows, size_t cols) {
  Array a({rows, cols});
  std::fill(a.mutable_data(), a.mutable_data() + rows * cols,
            std::numeric_limits<double>::quiet_NaN());
  return a;
}

// `items`, every one an instance of the same registered device, cast to its
// control-interface class T.
template <class T, class D>
std::vector<T*> Cast(const std::vector<D*>& items) {
  std::vector<T*> typed;
  typed.reserve(items.size());
  for (D* d : items) typed.push_back(dynamic_cast<T*>(d));
  return typed;
}

// Copies ring readings (proximity, ground, light: value and angle per
// sensor) into N x K arrays; a robot with fewer sensors than the widest has
// NaN in the columns it lacks.
template <class Ring>
void FillRing(const std::vector<const Ring*>& rings, bool with_angles, SensorArrays& out) {
  size_t width = 0;
  for (const Ring* r : rings) width = std::max(width, r->readings().size());
  bool ragged = false;
  for (const Ring* r : rings) ragged = ragged || r->readings().size() != width;
  Array values = ragged ? NanArray(rings.size(), width) : Array({rings.size(), width});
  double* v = values.mutable_data();
  for (size_t i = 0; i < rings.size(); ++i) {
    const auto& readings = rings[i]->readings();
    for (size_t k = 0; k < readings.size(); ++k) v[i * width + k] = readings[k].value;
  }
  out.values = values;
  if (!with_angles) return;
  Array angles = NanArray(rings.size(), width);
  double* a = angles.mutable_data();
  for (size_t i = 0; i < rings.size(); ++i) {
    const auto& readings = rings[i]->readings();
    for (size_t k = 0; k < readings.size(); ++k) a[i * width + k] = readings[k].angle;
  }
  out.angles = angles;
}

// Copies a sensor whose reading is a few numbers per robot into an N x C
// array (C = columns.size()), or N when `flat`.
template <class S, class Read>
void FillFixed(const std::vector<const S*>& sensors, std::vector<std::string> columns, bool flat,
               Read read, SensorArrays& out) {
  const size_t n = sensors.size(), c = columns.size();
  Array values = flat ? Array(std::vector<size_t>{n}) : Array({n, c});
  double* data = values.mutable_data();
  for (size_t i = 0; i < n; ++i) read(*sensors[i], data + i * c);
  out.values = values;
  out.columns = std::move(columns);
}

std::string ShapeText(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) {
    text += std::to_string(a.shape(d)) + (a.ndim() == 1 || d + 1 < a.ndim() ? "," : "");
    if (d + 1 < a.ndim()) text += " ";
  }
  return text + ")";
}

std::string TypeName(py::handle value) {
  return py::str(py::type::of(value).attr("__name__")).cast<std::string>();
}

// `value` as float64, an array of shape (n,) (a number is repeated).
py::array_t<double> PerRobot(py::handle value, size_t n, const std::string& what) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a) {
    PyErr_Clear();
    throw py::type_error(what + ": expected a number or an array of " + std::to_string(n) +
                         " numbers (one per robot), not " + TypeName(value));
  }
  if (a.ndim() == 0) {
    py::array_t<double> out(static_cast<py::ssize_t>(n));
    std::fill(out.mutable_data(), out.mutable_data() + n, *a.data());
    return out;
  }
  if (a.ndim() != 1 || static_cast<size_t>(a.shape(0)) != n) {
    throw py::value_error(what + ": expected " + std::to_string(n) +
                          " numbers (one per robot) or one number, not an array of shape " +
                          ShapeText(a));
  }
  return a;
}

void CheckFinite(const double* values, size_t n, const std::vector<std::string>& ids,
                 const std::string& what) {
  for (size_t i = 0; i < n; ++i) {
    if (std::isfinite(values[i])) continue;
    throw py::value_error(what + ": " + py::repr(py::float_(values[i])).cast<std::string>() +
                          " for robot '" + ids[i] + "' (row " + std::to_string(i) +
                          ") is not a finite number");
  }
}

void WriteSteering(const std::vector<DifferentialSteering*>& wheels,
                   const std::vector<std::string>& ids, const std::string& what,
                   py::handle command) {
  const size_t n = wheels.size();
  py::array_t<double> left, right;
  if (py::isinstance<py::tuple>(command) || py::isinstance<py::list>(command)) {
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(command);
    if (pair.size() != 2) {
      throw py::value_error(what + ": expected (left, right), not a " + TypeName(command) + " of " +
                            std::to_string(pair.size()) + " items");
    }
    left = PerRobot(pair[0], n, what + " left");
    right = PerRobot(pair[1], n, what + " right");
  } else {
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(command);
    if (!a) {
      PyErr_Clear();
      throw py::type_error(what + ": expected (left, right) or an N x 2 array, not " +
                           TypeName(command));
    }
    if (a.ndim() != 2 || static_cast<size_t>(a.shape(0)) != n || a.shape(1) != 2) {
      throw py::value_error(what + ": expected (left, right) or an array of shape (" +
                            std::to_string(n) + ", 2), not an array of shape " + ShapeText(a));
    }
    left = py::array_t<double>(static_cast<py::ssize_t>(n));
    right = py::array_t<double>(static_cast<py::ssize_t>(n));
    for (size_t i = 0; i < n; ++i) {
      left.mutable_data()[i] = a.data()[2 * i];
      right.mutable_data()[i] = a.data()[2 * i + 1];
    }
  }
  CheckFinite(left.data(), n, ids, what + " left");
  CheckFinite(right.data(), n, ids, what + " right");
  for (size_t i = 0; i < n; ++i) wheels[i]->SetLinearVelocity(left.data()[i], right.data()[i]);
}

void WriteLeds(const std::vector<Leds*>& leds, const std::vector<std::string>& ids,
               const std::string& what, py::handle command) {
  const size_t n = leds.size();
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(command);
  if (!a) {
    PyErr_Clear();
    throw py::type_error(what + ": expected an array of 0..255 integers, not " + TypeName(command));
  }
  const size_t k = leds.front()->count();
  const bool one = a.ndim() == 1 && a.shape(0) == 3;
  const bool per_robot = a.ndim() == 2 && static_cast<size_t>(a.shape(0)) == n && a.shape(1) == 3;
  const bool per_led = a.ndim() == 3 && static_cast<size_t>(a.shape(0)) == n &&
                       static_cast<size_t>(a.shape(1)) == k && a.shape(2) == 3;
  if (!one && !per_robot && !per_led) {
    throw py::value_error(what +
                          ": expected red, green, blue as an array of shape (3,) (every "
                          "robot), (" +
                          std::to_string(n) + ", 3) (each robot) or (" + std::to_string(n) + ", " +
                          std::to_string(k) + ", 3) (each LED), not " + ShapeText(a));
  }
  const double* data = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    const double c = data[i];
    if (c >= 0 && c <= 255 && c == std::floor(c)) continue;
    const size_t row = one ? 0 : static_cast<size_t>(i) / (per_led ? 3 * k : 3);
    throw py::value_error(what + ": " + py::repr(py::float_(c)).cast<std::string>() +
                          (one ? std::string() : " for robot '" + ids[row] + "'") +
                          " is not an integer from 0 to 255");
  }
  if (per_led) {
    for (size_t i = 0; i < n; ++i) {
      if (leds[i]->count() == k) continue;
      throw py::value_error(what + ": robot '" + ids[i] + "' has " +
                            std::to_string(leds[i]->count()) + " LEDs, not " + std::to_string(k) +
                            "; give one colour per robot (N x 3)");
    }
  }
  auto colour = [&](size_t at) {
    return Color{static_cast<uint8_t>(data[at]), static_cast<uint8_t>(data[at + 1]),
                 static_cast<uint8_t>(data[at + 2]), 255};
  };
  for (size_t i = 0; i < n; ++i) {
    if (per_led) {
      for (size_t j = 0; j < k; ++j) leds[i]->SetSingleColor(j, colour((i * k + j) * 3));
    } else {
      leds[i]->SetAllColors(colour(one ? 0 : i * 3));
    }
  }
}

}  // namespace

const char* const kArraySensors =
    "proximity, ground, light (values and angles, N x K), wheel_encoders (N x 2), positioning "
    "(N x 4), imu (N x 6), battery (N)";
const char* const kArrayActuators =
    "differential_steering ((left, right) m/s, or N x 2), leds (N x 3 or N x K x 3, 0..255)";

bool ReadSensorArrays(const std::vector<Sensor*>& sensors, bool with_angles, SensorArrays& out) {
  // Every robot's instance of one registered sensor is of one class: the
  // first tells which.
  const Sensor* first = sensors.front();
  if (dynamic_cast<const ProximitySensor*>(first)) {
    FillRing(Cast<const ProximitySensor>(sensors), with_angles, out);
  } else if (dynamic_cast<const GroundSensor*>(first)) {
    FillRing(Cast<const GroundSensor>(sensors), with_angles, out);
  } else if (dynamic_cast<const LightSensor*>(first)) {
    FillRing(Cast<const LightSensor>(sensors), with_angles, out);
  } else if (dynamic_cast<const WheelEncoders*>(first)) {
    FillFixed(
        Cast<const WheelEncoders>(sensors), {"distance_left", "distance_right"}, false,
        [](const WheelEncoders& s, double* row) {
          row[0] = s.distance_left();
          row[1] = s.distance_right();
        },
        out);
  } else if (dynamic_cast<const PositioningSensor*>(first)) {
    FillFixed(
        Cast<const PositioningSensor>(sensors), {"x", "y", "z", "yaw"}, false,
        [](const PositioningSensor& s, double* row) {
          row[0] = s.x();
          row[1] = s.y();
          row[2] = s.z();
          row[3] = s.yaw();
        },
        out);
  } else if (dynamic_cast<const Imu*>(first)) {
    FillFixed(
        Cast<const Imu>(sensors),
        {"angular_velocity_x", "angular_velocity_y", "angular_velocity_z", "acceleration_x",
         "acceleration_y", "acceleration_z"},
        false,
        [](const Imu& s, double* row) {
          for (int k = 0; k < 3; ++k) {
            row[k] = s.angular_velocity()[k];
            row[3 + k] = s.acceleration()[k];
          }
        },
        out);
  } else if (dynamic_cast<const Battery*>(first)) {
    FillFixed(
        Cast<const Battery>(sensors), {"level"}, true,
        [](const Battery& s, double* row) { row[0] = s.level(); }, out);
  } else {
    return false;
  }
  return true;
}

bool WriteActuatorArrays(const std::vector<Actuator*>& actuators,
                         const std::vector<std::string>& ids, const std::string& what,
                         py::handle command) {
  const Actuator* first = actuators.front();
  if (dynamic_cast<const DifferentialSteering*>(first)) {
    WriteSteering(Cast<DifferentialSteering>(actuators), ids, what, command);
  } else if (dynamic_cast<const Leds*>(first)) {
    WriteLeds(Cast<Leds>(actuators), ids, what, command);
  } else {
    return false;
  }
  return true;
}

py::object ReadActuatorArrays(const std::vector<Actuator*>& actuators) {
  const size_t n = actuators.size();
  if (dynamic_cast<const DifferentialSteering*>(actuators.front())) {
    Array out({n, size_t{2}});
    double* data = out.mutable_data();
    for (size_t i = 0; i < n; ++i) {
      const auto* wheels = dynamic_cast<const DifferentialSteering*>(actuators[i]);
      data[2 * i] = wheels->target_left();
      data[2 * i + 1] = wheels->target_right();
    }
    return out;
  }
  if (dynamic_cast<const Leds*>(actuators.front())) {
    const std::vector<const Leds*> leds = Cast<const Leds>(actuators);
    size_t k = 0;
    for (const Leds* l : leds) k = std::max(k, l->count());
    py::array_t<uint8_t> out({n, k, size_t{3}});
    uint8_t* data = out.mutable_data();
    std::fill(data, data + n * k * 3, 0);
    for (size_t i = 0; i < n; ++i) {
      for (size_t j = 0; j < leds[i]->count(); ++j) {
        const Color c = leds[i]->colors()[j];
        uint8_t* at = data + (i * k + j) * 3;
        at[0] = c.r;
        at[1] = c.g;
        at[2] = c.b;
      }
    }
    return out;
  }
  return py::none();
}

}  // namespace colony::python
