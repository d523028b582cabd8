// The per-robot Python controller host: <python_controller> with
// <params module="m" class="C"/> (docs/python.md, "Per-robot controllers").
//
// One Python object per robot, as a C++ controller: created with no
// arguments, then init(params) (if defined); step(readings) -> commands
// every tick with that robot's readings (readings["proximity"]: 24 numbers)
// and the same device names as C++ controllers; reset() and destroy() (if
// defined) when the simulation resets or ends. Simple and slow: the objects
// are stepped one after the other, in robot order, on the thread that steps
// the simulation (through the core's ControllerBatch hook), so the GIL is
// taken once per tick and the run is deterministic whatever the thread count.
#include <memory>
#include <string>
#include <vector>

#include "core/log.h"
#include "core/registry.h"
#include "python/python_host.h"

namespace colony::python {
namespace {

class PythonController : public Controller {
 public:
  void Init(const Params& params) override {
    EnsureInterpreter();
    py::gil_scoped_acquire gil;
    user_ = ImportUserClass(params);
    sensors_ = SensorNames(devices());
    actuators_ = ActuatorNames(devices());
    where_ = user_.name + ".step() of robot '" + id() + "' (" + user_.file + ")";
    CheckArraySensors(devices());
    try {
      object_ = user_.cls();
      object_.attr("robot_id") = id();
      if (py::hasattr(object_, "init")) object_.attr("init")(UserParams(params));
      step_ = object_.attr("step");
    } catch (py::error_already_set& e) {
      throw std::runtime_error("Python class " + user_.Describe() + " failed to start on robot '" +
                               id() + "': " + PythonError(e));
    }
  }

  ~PythonController() override {
    if (!PythonAlive()) {
      object_.release();
      step_.release();
      user_.cls.release();
      for (auto& a : angles_) a.release();
      return;
    }
    py::gil_scoped_acquire gil;
    object_ = py::object();
    step_ = py::object();
    user_.cls = py::object();
    angles_.clear();
  }

  // The batch steps the objects.
  void ControlStep() override {}

  // Called with the GIL held, by the batch.
  void StepPython() {
    Controller* self = this;
    const std::vector<Controller*> one{self};
    py::dict readings = Readings(one, sensors_, angles_, true);
    py::object commands;
    try {
      commands = step_(readings);
    } catch (py::error_already_set& e) {
      throw std::runtime_error("Python error in " + where_ + ": " + PythonError(e));
    }
    ApplyCommands(commands, one, {id()}, actuators_, where_);
  }

  void Reset() override { Call("reset"); }

  void Destroy() override {
    try {
      Call("destroy");
    } catch (const std::exception& e) {
      // Destroy runs while the simulation is torn down: it cannot fail the run.
      Log(LogLevel::kError, "robot '" + id() + "': " + e.what());
    }
  }

  std::unique_ptr<ControllerBatch> NewBatch() override;

 private:
  void Call(const char* method) {
    if (!object_ || !PythonAlive()) return;
    py::gil_scoped_acquire gil;
    if (!py::hasattr(object_, method)) return;
    try {
      object_.attr(method)();
    } catch (py::error_already_set& e) {
      throw std::runtime_error("Python error in " + user_.name + "." + method + "() of robot '" +
                               id() + "' (" + user_.file + "): " + PythonError(e));
    }
  }

  UserClass user_;
  py::object object_, step_;
  std::vector<DeviceName> sensors_, actuators_;
  std::vector<py::object> angles_;
  std::string where_;
};

// Steps every robot's object in robot order, taking the GIL once.
class PerRobot : public ControllerBatch {
 public:
  void Step(const std::vector<Controller*>& members) override {
    py::gil_scoped_acquire gil;
    for (Controller* c : members) static_cast<PythonController*>(c)->StepPython();
  }
};

std::unique_ptr<ControllerBatch> PythonController::NewBatch() {
  return std::make_unique<PerRobot>();
}

COLONY_REGISTER_CONTROLLER(
    PythonController, "python_controller",
    "a Python object per robot: init(params), step(readings) -> commands, reset(), destroy()",
    {{"module", "a Python module name", "",
      "the module (m.py beside the experiment file, in path, or on sys.path)"},
     {"class", "a class name", "",
      "its class: C(), then init(params), step(readings) -> commands, reset(), destroy()"},
     {"path", "a folder (relative: to the experiment file's)", "",
      "looked for the module in first"},
     {"*", "any other name", "", "reaches init() as params (int, float, bool or str)"}});

}  // namespace
}  // namespace colony::python
