// A test-only loop functions for the sweep tests: one metric, named by
// params name (default "value"), worth scale x tick + seed at every tick
// from tick 0, so that a test can check statistics over seeds by hand.
// With params table="NAME", it also writes a row (tick, seed) per tick into
// the run folder's table NAME, through the run-folder API.
#include "core/loop_functions.h"
#include "core/simulation.h"
#include "core/table_writer.h"

namespace colony {
namespace {

class SweepMetrics : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    name_ = params.GetString("name", "value");
    scale_ = params.GetDouble("scale", 1);
    const std::string table = params.GetString("table", "");
    if (!table.empty()) {
      table_ = Table::InRunFolder(sim(), table,
                                  {{"tick", ColumnType::kInteger}, {"seed", ColumnType::kInteger}});
    }
    PostStep();
  }
  void PostStep() override {
    sim().metrics().Set(
        name_, scale_ * static_cast<double>(sim().tick()) + static_cast<double>(sim().seed()));
    if (table_.writing()) {
      table_.Integer(static_cast<int64_t>(sim().tick()))
          .Integer(static_cast<int64_t>(sim().seed()))
          .EndRow();
    }
  }

 private:
  std::string name_;
  double scale_ = 1;
  Table table_;
};

COLONY_REGISTER_LOOP_FUNCTIONS(SweepMetrics, "sweep_metrics",
                               "test only: one metric, scale x tick + seed",
                               {{"name", "a name", "value", "the metric's name"},
                                {"scale", "a number", "1", "its growth per tick"},
                                {"table", "a file name", "",
                                 "a table (tick, seed) written into the run folder"}});

}  // namespace
}  // namespace colony
