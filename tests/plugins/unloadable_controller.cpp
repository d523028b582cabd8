// A test controller plugin that cannot be loaded: it calls a function no
// library defines, so dlopen (RTLD_NOW) fails with "undefined symbol". An
// experiment naming <unloadable_controller> must be told that, not that the
// controller is unknown.
#include "core/control_interface.h"
#include "core/registry.h"

extern "C" void colony_test_function_no_library_defines();

namespace {

class Unloadable : public colony::Controller {
 public:
  void ControlStep() override { colony_test_function_no_library_defines(); }
};

COLONY_REGISTER_CONTROLLER(Unloadable, "unloadable_controller", "test: cannot be loaded");

}  // namespace
