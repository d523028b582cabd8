// A test-only controller for the sweep and reliability tests: at its first
// control step it appends a line to params count_file (if given), so a test
// can count how often runs really ran; then, from tick params at (default 1)
// on, it does what params mode says: "none" (nothing), "crash" (abort),
// "hang" (wait forever), "segfault" (writes through a null pointer),
// "throw_int" (throws an int, not a std::exception) or "slow" (sleeps a
// millisecond every step, so a test can interrupt a run part-way).
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <fstream>
#include <string>

#include "core/control_interface.h"
#include "core/registry.h"

namespace {

class SweepMisbehave : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    mode_ = params.GetString("mode", "none");
    at_ = params.GetInt("at", 1, 1);
    count_file_ = params.GetString("count_file", "");
  }

  void ControlStep() override {
    if (++ticks_ == 1 && !count_file_.empty()) std::ofstream(count_file_, std::ios::app) << "ran\n";
    if (ticks_ < at_) return;
    if (mode_ == "crash") std::abort();
    if (mode_ == "hang") {
      for (;;) pause();
    }
    if (mode_ == "segfault") {
      volatile int* volatile nowhere = nullptr;
      *nowhere = 1;
    }
    if (mode_ == "throw_int") throw 42;
    if (mode_ == "slow") usleep(1000);
  }

 private:
  std::string mode_, count_file_;
  int64_t at_ = 1, ticks_ = 0;
};

COLONY_REGISTER_CONTROLLER(
    SweepMisbehave, "sweep_misbehave",
    "test only: crashes or hangs on demand; params mode (none, crash, hang, segfault, throw_int, "
    "slow), at (tick), "
    "count_file (a line appended per run)");

}  // namespace
