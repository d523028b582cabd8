// The batched Python controller host: <python_batch_controller> with
// <params module="m" class="C"/> (docs/python.md, "Batched controllers").
//
// One Python object per controller configuration steps all its robots at
// once: every tick, after the robots' sensors were read, its step(readings)
// gets a dict of numpy arrays (readings["proximity"]: N x 24, one row per
// robot in robot order) and returns a dict of commands
// ({"differential_steering": (left, right)}), which are written into the
// robots' actuators as a C++ controller's calls would. The simulation calls
// it through the core's ControllerBatch hook, on the thread that steps it,
// with the GIL taken only for that call: the robots' sensing stays
// parallel, and the run is deterministic whatever the thread count.
#include <pybind11/numpy.h>

#include <memory>
#include <string>
#include <vector>

#include "core/registry.h"
#include "python/python_host.h"

namespace colony::python {
namespace {

class PythonBatch : public ControllerBatch {
 public:
  PythonBatch(UserClass user, py::dict params, const DeviceTable& devices)
      : user_(std::move(user)),
        sensors_(SensorNames(devices)),
        actuators_(ActuatorNames(devices)),
        where_(user_.name + ".step() (" + user_.file + ")") {
    CheckArraySensors(devices);  // at load, not at the first step
    try {
      instance_ = user_.cls(params);
      step_ = instance_.attr("step");
    } catch (py::error_already_set& e) {
      throw std::runtime_error("Python class " + user_.Describe() +
                               " could not be created: " + PythonError(e));
    }
  }

  ~PythonBatch() override {
    if (!PythonAlive()) {
      // Shutting down: the objects are left to the interpreter.
      instance_.release();
      step_.release();
      for (auto& a : angles_) a.release();
      user_.cls.release();
      return;
    }
    py::gil_scoped_acquire gil;
    instance_ = py::object();
    step_ = py::object();
    angles_.clear();
    user_.cls = py::object();
  }

  void Step(const std::vector<Controller*>& members) override {
    py::gil_scoped_acquire gil;
    if (members != members_) {
      members_ = members;
      ids_.clear();
      for (const Controller* c : members) ids_.push_back(c->id());
      angles_.clear();
    }
    py::dict readings = Readings(members, sensors_, angles_, false);
    py::object commands;
    try {
      commands = step_(readings);
    } catch (py::error_already_set& e) {
      throw std::runtime_error("Python error in " + where_ + ": " + PythonError(e));
    }
    ApplyCommands(commands, members, ids_, actuators_, where_);
  }

 private:
  UserClass user_;
  std::vector<DeviceName> sensors_, actuators_;
  std::string where_;
  py::object instance_, step_;
  // The members of the last tick, their ids, and the ring sensors' angles
  // (read-only arrays, kept while the members stay the same).
  std::vector<Controller*> members_;
  std::vector<std::string> ids_;
  std::vector<py::object> angles_;
};

// Each robot's controller is an empty shell: the configuration's first one
// creates the batch, which holds the Python object.
class PythonBatchController : public Controller {
 public:
  void Init(const Params& params) override {
    // Required; every other parameter reaches the class.
    params.GetString("module");
    params.GetString("class");
    params.GetString("path", "");
    for (const auto& key : params.Unread()) params.GetString(key, "");
    params_ = &params;  // the configuration's, which outlives its controllers
  }

  void ControlStep() override {}

  std::unique_ptr<ControllerBatch> NewBatch() override {
    EnsureInterpreter();
    py::gil_scoped_acquire gil;
    UserClass user = ImportUserClass(*params_);
    py::dict params = UserParams(*params_);
    return std::make_unique<PythonBatch>(std::move(user), std::move(params), devices());
  }

 private:
  const Params* params_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(
    PythonBatchController, "python_batch_controller",
    "a Python class steps all the configuration's robots at once over numpy arrays",
    {{"module", "a Python module name", "",
      "the module (m.py beside the experiment file, in path, or on sys.path)"},
     {"class", "a class name", "", "its class: Class(params), step(readings) -> commands"},
     {"path", "a folder (relative: to the experiment file's)", "",
      "looked for the module in first"},
     {"*", "any other name", "", "reaches the class as params (int, float, bool or str)"}});

}  // namespace
}  // namespace colony::python
