// How long Simulation::Reset takes beside a new simulation, for an
// evaluation loop's budget (docs/embedding.md): loads (and deletes) the
// experiment `--repeats` times, then resets one simulation `--repeats` times
// (seeds 1, 2, ...), and prints the median of each. A Reset deletes the
// world and builds it again, so it compares with a load plus a delete. Each
// reset is checked against a fresh load with its seed (the same state
// hash), outside the timed part.
//
//   colony_reset_timing experiments/benchmarks/diffusion_1000.xml [--repeats 10] [--threads 1]
//
// Exit status: 0, 2 bad input, 1 a reset that differs from a fresh load or a failure.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/simulation.h"

namespace {

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

int Run(const std::string& file, int repeats, int threads) {
  colony::ExperimentOptions options;
  options.file = file;
  options.threads = threads;
  // Loads: reading the file (and its plugin libraries, loaded once per
  // process) and building; then deleting.
  std::vector<double> loads, deletes, resets;
  std::vector<uint64_t> fresh_hashes;
  for (int i = 1; i <= repeats; ++i) {
    options.seed = static_cast<uint64_t>(i);
    auto start = std::chrono::steady_clock::now();
    auto sim = colony::Simulation::Load(options);
    loads.push_back(Seconds(start));
    fresh_hashes.push_back(sim->StateHash());
    start = std::chrono::steady_clock::now();
    sim.reset();
    deletes.push_back(Seconds(start));
  }
  // Resets of one simulation, run one tick in between so there is
  // something to put back.
  options.seed = 0;
  auto sim = colony::Simulation::Load(options);
  int differing = 0;
  for (int i = 1; i <= repeats; ++i) {
    sim->Step();
    const auto start = std::chrono::steady_clock::now();
    sim->Reset(static_cast<uint64_t>(i));
    resets.push_back(Seconds(start));
    differing += sim->StateHash() != fresh_hashes[i - 1];
  }
  const double load = Median(loads), remove = Median(deletes), reset = Median(resets);
  std::printf("%s: %zu robots, %d thread(s); medians over %d\n", file.c_str(), sim->robot_count(),
              sim->threads(), repeats);
  std::printf("load (read the file, build): %.2f ms; delete: %.2f ms\n", 1e3 * load, 1e3 * remove);
  std::printf(
      "Reset (delete, build with a new seed; no file read): %.2f ms (%.2fx load + delete)\n",
      1e3 * reset, reset / (load + remove));
  std::printf("state after each Reset = a fresh load with its seed: %s\n",
              differing ? "NO" : "yes");
  return differing ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Times Simulation::Reset against loading the same experiment."};
  std::string file;
  int repeats = 10, threads = 1;
  app.add_option("experiment", file, "an experiment file")->required()->check(CLI::ExistingFile);
  app.add_option("--repeats", repeats, "loads and resets to time")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--threads", threads, "threads stepping the simulation")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "colony_reset_timing: %s (see --help)\n", e.what());
    return 2;
  }
  try {
    return Run(file, repeats, threads);
  } catch (const colony::ConfigError& e) {
    std::fprintf(stderr, "colony_reset_timing: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "colony_reset_timing: %s\n", e.what());
    return 1;
  }
}
