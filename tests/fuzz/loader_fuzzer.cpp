// Fuzz target for the experiment loader: any byte string given as an
// experiment file must either load (and then run a few ticks) or be refused
// with a ConfigError; a RuntimeFailure during those ticks is also a clean
// refusal. Anything else (a crash, a sanitizer report, another exception, a
// hang) is a bug.
//
// Built two ways (tests/fuzz/CMakeLists.txt): with libFuzzer (clang,
// -DCOLONY_BUILD_FUZZERS=ON) as `loader_fuzzer`, and with any compiler as
// `loader_fuzz_replay`, which feeds it the files named on its command line:
// the ctest regression tests run the corpus and every crash found so far
// (tests/fuzz/regressions) through it. Run from the source folder, so the
// experiments' relative paths resolve.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "core/simulation.h"

namespace {

// Ticks run for an input that loads: enough to step every engine, device and
// controller a few times, few enough to keep many inputs a second.
constexpr int kTicks = 3;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  colony::ExperimentOptions options;
  options.file = "fuzz_input.xml";
  options.text.assign(reinterpret_cast<const char*>(data), size);
  options.threads = 1;
  try {
    auto sim = colony::Simulation::Load(options);
    for (int i = 0; i < kTicks && !sim->Done(); ++i) sim->Step();
  } catch (const colony::ConfigError&) {
  } catch (const colony::RuntimeFailure&) {
  }
  return 0;
}
