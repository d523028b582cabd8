#include "python/python_host.h"

#include <pybind11/numpy.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "python/device_arrays.h"

namespace colony::python {

void EnsureInterpreter() {
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  if (Py_IsInitialized()) return;
  // The interpreter the module was built for: named as the program, so that
  // Python finds its own library and packages (Debian's numpy) rather than
  // those of whichever python3 is first on PATH.
  PyConfig config;
  PyConfig_InitPythonConfig(&config);
  config.install_signal_handlers = 0;  // Ctrl-C stays the host program's
  config.parse_argv = 0;
  PyStatus status =
      PyConfig_SetBytesString(&config, &config.program_name, COLONY_PYTHON_EXECUTABLE);
  if (!PyStatus_Exception(status)) status = Py_InitializeFromConfig(&config);
  PyConfig_Clear(&config);
  if (PyStatus_Exception(status)) {
    throw std::runtime_error(std::string("could not start Python (") + COLONY_PYTHON_EXECUTABLE +
                             "): " + (status.err_msg ? status.err_msg : "no reason given"));
  }
  // Every call into Python takes the GIL (py::gil_scoped_acquire), from
  // whichever thread steps the simulation.
  PyEval_SaveThread();
}

bool PythonAlive() { return Py_IsInitialized() && !_Py_IsFinalizing(); }

std::string UserClass::Describe() const {
  return name + " (module '" + module + "', " + file + ")";
}

namespace {

// The folders the user's module is looked for in first: path= (relative to
// the experiment file's folder), then that folder.
std::vector<std::string> ModuleFolders(const Params& params) {
  const std::string base = params.base_directory().empty() ? "." : params.base_directory();
  std::vector<std::string> folders;
  const std::string path = params.GetString("path", "");
  if (!path.empty()) {
    const std::filesystem::path p(path);
    folders.push_back(
        (p.is_absolute() ? p : std::filesystem::path(base) / p).lexically_normal().string());
    if (!std::filesystem::is_directory(folders.back())) {
      throw ParamError("path", path, "no folder '" + folders.back() + "'");
    }
  }
  folders.push_back(std::filesystem::absolute(base).lexically_normal().string());
  return folders;
}

}  // namespace

UserClass ImportUserClass(const Params& params) {
  UserClass user;
  user.module = params.GetString("module");
  user.name = params.GetString("class");
  const std::vector<std::string> folders = ModuleFolders(params);
  py::list sys_path = py::module_::import("sys").attr("path");
  for (auto it = folders.rbegin(); it != folders.rend(); ++it) {
    if (!sys_path.contains(*it)) sys_path.insert(0, *it);
  }
  py::module_ module;
  try {
    module = py::module_::import(user.module.c_str());
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_ModuleNotFoundError) &&
        py::str(e.value().attr("name")).cast<std::string>() == user.module) {
      std::string where;
      for (const auto& f : folders) where += (where.empty() ? "" : ", ") + f;
      throw ParamError("module", user.module,
                       "no Python module '" + user.module + "' (looked for " + user.module +
                           ".py in " + where + ", then on sys.path)");
    }
    throw ParamError("module", user.module,
                     "Python module '" + user.module + "' failed to import: " + PythonError(e));
  }
  user.file = py::hasattr(module, "__file__") ? py::str(module.attr("__file__")).cast<std::string>()
                                              : "(built in)";
  if (!py::hasattr(module, user.name.c_str())) {
    std::string classes;
    for (auto item : module.attr("__dict__").cast<py::dict>()) {
      if (PyType_Check(item.second.ptr()) &&
          py::str(item.second.attr("__module__")).cast<std::string>() == user.module) {
        classes += (classes.empty() ? "" : ", ") + item.first.cast<std::string>();
      }
    }
    throw ParamError("class", user.name,
                     "Python module '" + user.module + "' (" + user.file + ") has no class '" +
                         user.name +
                         "'; its classes: " + (classes.empty() ? std::string("none") : classes));
  }
  user.cls = module.attr(user.name.c_str());
  if (!PyType_Check(user.cls.ptr())) {
    throw ParamError("class", user.name,
                     "'" + user.name + "' in Python module '" + user.module + "' (" + user.file +
                         ") is not a class");
  }
  if (!py::hasattr(user.cls, "step")) {
    throw ParamError("class", user.name,
                     "Python class " + user.Describe() + " has no method step()");
  }
  return user;
}

py::dict UserParams(const Params& params) {
  py::dict out;
  for (const auto& key : params.Unread()) params.GetString(key, "");
  for (const auto& key : params.Asked()) {
    if (key == "module" || key == "class" || key == "path" || !params.Has(key)) continue;
    const std::string text = params.GetString(key, "");
    py::object value = py::str(text);
    if (text == "true" || text == "false") {
      value = py::bool_(text == "true");
    } else if (!text.empty()) {
      char* end = nullptr;
      errno = 0;
      const long long i = std::strtoll(text.c_str(), &end, 10);
      if (*end == '\0' && errno == 0) {
        value = py::int_(i);
      } else {
        const double d = std::strtod(text.c_str(), &end);
        if (*end == '\0') value = py::float_(d);
      }
    }
    out[py::str(key)] = value;
  }
  return out;
}

std::string PythonError(py::error_already_set& e) {
  try {
    py::object format = py::module_::import("traceback").attr("format_exception");
    std::string text;
    // No traceback (an error raised before any frame ran, a SyntaxError): None.
    py::object trace = e.trace() ? py::reinterpret_borrow<py::object>(e.trace()) : py::none();
    for (auto line : format(e.type(), e.value(), trace)) text += line.cast<std::string>();
    while (!text.empty() && text.back() == '\n') text.pop_back();
    return "\n" + text;
  } catch (const std::exception&) {
    return e.what();
  }
}

namespace {

// readings[label + suffix] (and [name + suffix] when the file used an alias).
void Put(py::dict& readings, const DeviceName& d, const char* suffix, py::handle value) {
  readings[py::str(d.label + suffix)] = value;
  if (d.name != d.label) readings[py::str(d.name + suffix)] = value;
}

}  // namespace

std::vector<DeviceName> SensorNames(const DeviceTable& devices) {
  std::vector<DeviceName> out;
  for (size_t i = 0; i < devices.labels->sensor_labels->size(); ++i)
    out.push_back({(*devices.labels->sensor_labels)[i], devices.labels->SensorName(i)});
  return out;
}

std::vector<DeviceName> ActuatorNames(const DeviceTable& devices) {
  std::vector<DeviceName> out;
  for (size_t i = 0; i < devices.labels->actuator_labels->size(); ++i)
    out.push_back({(*devices.labels->actuator_labels)[i], devices.labels->ActuatorName(i)});
  return out;
}

void CheckArraySensors(const DeviceTable& devices) {
  for (size_t i = 0; i < devices.labels->sensor_labels->size(); ++i) {
    SensorArrays probe;
    if (!ReadSensorArrays({devices.sensors[i]}, false, probe)) {
      throw std::runtime_error(
          "sensor '" + (*devices.labels->sensor_labels)[i] +
          "' has no array form for Python controllers; those that have: " + kArraySensors);
    }
  }
}

py::dict Readings(const std::vector<Controller*>& members, const std::vector<DeviceName>& sensors,
                  std::vector<py::object>& angles, bool row) {
  py::dict readings;
  std::vector<Sensor*> instances(members.size());
  angles.resize(sensors.size());
  for (size_t j = 0; j < sensors.size(); ++j) {
    for (size_t i = 0; i < members.size(); ++i) instances[i] = members[i]->devices().sensors[j];
    SensorArrays arrays;
    ReadSensorArrays(instances, !angles[j] || angles[j].is_none(), arrays);
    if (!arrays.angles.is_none()) {
      angles[j] = row ? py::object(arrays.angles[py::int_(0)]) : arrays.angles;
      angles[j].attr("setflags")(py::arg("write") = false);
    } else if (!angles[j]) {
      angles[j] = py::none();
    }
    Put(readings, sensors[j], "", row ? py::object(arrays.values[py::int_(0)]) : arrays.values);
    if (!angles[j].is_none()) Put(readings, sensors[j], "_angles", angles[j]);
  }
  return readings;
}

void ApplyCommands(const py::object& commands, const std::vector<Controller*>& members,
                   const std::vector<std::string>& ids, const std::vector<DeviceName>& actuators,
                   const std::string& where) {
  if (commands.is_none()) return;  // no new commands this tick
  if (!py::isinstance<py::dict>(commands)) {
    throw std::runtime_error(
        where + " returned a " +
        py::str(py::type::of(commands).attr("__name__")).cast<std::string>() +
        "; it returns a dict of actuator name to commands, e.g. {\"differential_steering\": "
        "(left, right)}, or None");
  }
  std::vector<Actuator*> instances(members.size());
  for (auto item : commands.cast<py::dict>()) {
    if (!py::isinstance<py::str>(item.first)) {
      throw std::runtime_error(where + " returned a key " +
                               py::repr(item.first).cast<std::string>() +
                               " that is not an actuator name (str)");
    }
    const std::string key = item.first.cast<std::string>();
    size_t j = 0;
    while (j < actuators.size() && actuators[j].label != key && actuators[j].name != key) ++j;
    if (j == actuators.size()) {
      std::string declared;
      for (const auto& a : actuators) declared += (declared.empty() ? "" : ", ") + a.label;
      throw std::runtime_error(where + " returned commands for '" + key +
                               "', which is not among the controller's <actuators> (" +
                               (declared.empty() ? std::string("none") : declared) + ")");
    }
    for (size_t i = 0; i < members.size(); ++i) instances[i] = members[i]->devices().actuators[j];
    bool written = false;
    try {
      written = WriteActuatorArrays(instances, ids, key, item.second);
    } catch (const py::builtin_exception& e) {
      throw std::runtime_error(where + " returned bad commands: " + e.what());
    }
    if (!written) {
      throw std::runtime_error(
          where + " returned commands for '" + key +
          "', which takes no arrays from Python yet; those that do: " + kArrayActuators);
    }
  }
}

}  // namespace colony::python
