// A test-only loop functions for the sweep tests: one metric, named by
// params name (default "value"), worth scale x tick + seed at every tick
// from tick 0, so that a test can check statistics over seeds by hand.
#include "core/loop_functions.h"
#include "core/simulation.h"

namespace colony {
namespace {

class SweepMetrics : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    name_ = params.GetString("name", "value");
    scale_ = params.GetDouble("scale", 1);
    PostStep();
  }
  void PostStep() override {
    sim().metrics().Set(
        name_, scale_ * static_cast<double>(sim().tick()) + static_cast<double>(sim().seed()));
  }

 private:
  std::string name_;
  double scale_ = 1;
};

COLONY_REGISTER_LOOP_FUNCTIONS(SweepMetrics, "sweep_metrics",
                               "test only: one metric, scale x tick + seed",
                               {{"name", "a name", "value", "the metric's name"},
                                {"scale", "a number", "1", "its growth per tick"}});

}  // namespace
}  // namespace colony
