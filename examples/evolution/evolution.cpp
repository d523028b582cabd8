// Evolution in one process: evaluates parameter sets of the diffusion
// controller with one loaded simulation, as a genetic algorithm's loop
// does (docs/embedding.md). The experiment is loaded once; then for each
// set: its parameters are given to the controller configuration
// (Simulation::SetControllerParam), the simulation is Reset with each
// trial's seed (nothing is read again, no library loaded again), run to
// its end, and the fitness read from the loop functions' metrics.
//
// The sets come from a (1+1) evolution strategy: the first is the
// controller's defaults (velocity 0.05 m/s, alpha 7.5 degrees, delta 0.1);
// each next one is the best so far with
// Gaussian noise added, and replaces it when it is fitter. Every set is
// tried on the same seeds (1, 2, ...), so they are compared on the same
// starting positions.
//
// Fitness, from the diffusion_metrics loop functions: how far the robots
// spread from where they started, less what they spent blocked:
//   mean_displacement (m) - 0.1 m x the mean time a robot spent in contact (s)
//
//   colony_evolution experiments/diffusion.xml [--sets 20] [--trials 2] [--seconds 60]
//
// Exit status: 0, 2 bad input (command line, experiment), 1 failure while running.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

#include "core/error.h"
#include "core/random.h"
#include "core/simulation.h"

namespace {

// One point of the search: the diffusion controller's parameters.
struct Genome {
  double velocity = 0.05;  // m/s, in [0.02, 0.3] (a marXbot's top speed)
  double alpha = 7.5;      // degrees, in [1, 90]
  double delta = 0.1;      // proximity vector length that counts as an obstacle, in [0.01, 1]
};

// `g` with Gaussian noise added, each parameter kept in its range.
Genome Mutate(const Genome& g, colony::RandomStream& rng) {
  Genome m;
  m.velocity = std::clamp(rng.Gaussian(g.velocity, 0.04), 0.02, 0.3);
  m.alpha = std::clamp(rng.Gaussian(g.alpha, 10.0), 1.0, 90.0);
  m.delta = std::clamp(rng.Gaussian(g.delta, 0.1), 0.01, 1.0);
  return m;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

struct Timing {
  double resets = 0, runs = 0;  // seconds, summed
  int count = 0;
};

// The fitness of the simulation's state now (see the header).
double Fitness(const colony::Simulation& sim) {
  const colony::Metrics& m = sim.metrics();
  const double robots = m.Value("robots");
  const double blocked_seconds = robots > 0 ? m.Value("contact_ticks") * sim.dt() / robots : 0;
  return m.Value("mean_displacement") - 0.1 * blocked_seconds;
}

// Gives `genome` to the controller configuration `controller`, for the
// controllers the next Reset builds. Throws std::invalid_argument when the
// experiment has no such configuration.
void Apply(colony::Simulation& sim, const std::string& controller, const Genome& genome) {
  sim.SetControllerParam(controller, "velocity", std::to_string(genome.velocity));
  sim.SetControllerParam(controller, "alpha", std::to_string(genome.alpha));
  sim.SetControllerParam(controller, "delta", std::to_string(genome.delta));
}

// The mean fitness of `genome` over `trials` runs (seeds 1..trials).
double Evaluate(colony::Simulation& sim, const std::string& controller, const Genome& genome,
                int trials, Timing& timing) {
  Apply(sim, controller, genome);
  double sum = 0;
  for (int trial = 1; trial <= trials; ++trial) {
    auto start = std::chrono::steady_clock::now();
    sim.Reset(static_cast<uint64_t>(trial));
    timing.resets += Seconds(start);
    start = std::chrono::steady_clock::now();
    while (!sim.Done()) sim.Step();
    timing.runs += Seconds(start);
    ++timing.count;
    sum += Fitness(sim);
  }
  return sum / trials;
}

int Run(const std::string& file, const std::string& controller, int sets, int trials,
        double seconds, int threads) {
  colony::ExperimentOptions options;
  options.file = file;
  options.threads = threads;
  options.overrides = {"framework.experiment.length=" + std::to_string(seconds)};
  auto start = std::chrono::steady_clock::now();
  auto sim = colony::Simulation::Load(options);
  const double load_seconds = Seconds(start);
  // What the search needs is there before anything runs: the metrics (set
  // by the loop functions' Init) and the controller configuration.
  try {
    Fitness(*sim);
  } catch (const std::out_of_range& e) {
    std::fprintf(stderr, "colony_evolution: %s; %s needs the diffusion_metrics loop functions\n",
                 e.what(), file.c_str());
    return 2;
  }
  try {
    Apply(*sim, controller, Genome());
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "colony_evolution: %s (--controller)\n", e.what());
    return 2;
  }
  std::printf("%s: %zu robots, %llu ticks a run, %d trial(s) a set; loaded in %.1f ms\n",
              file.c_str(), sim->robot_count(),
              static_cast<unsigned long long>(sim->length_ticks()), trials, 1e3 * load_seconds);
  std::printf("%4s  %9s  %6s  %6s  %8s\n", "set", "velocity", "alpha", "delta", "fitness");

  colony::RandomStream rng(2024);  // the search's own stream: the same sets every time
  Genome best;
  double best_fitness = 0;
  int best_set = 0;
  Timing timing;
  for (int set = 1; set <= sets; ++set) {
    const Genome genome = set == 1 ? best : Mutate(best, rng);
    const double fitness = Evaluate(*sim, controller, genome, trials, timing);
    const bool better = set == 1 || fitness > best_fitness;
    if (better) {
      best = genome;
      best_fitness = fitness;
      best_set = set;
    }
    std::printf("%4d  %9.4f  %6.2f  %6.3f  %8.4f%s\n", set, genome.velocity, genome.alpha,
                genome.delta, fitness, better ? "  best so far" : "");
    std::fflush(stdout);
  }
  std::printf("best: set %d, velocity=%.4f alpha=%.2f delta=%.3f, fitness %.4f\n", best_set,
              best.velocity, best.alpha, best.delta, best_fitness);
  std::printf("%d runs in one process: Reset %.2f ms on average, a run %.1f ms on average\n",
              timing.count, 1e3 * timing.resets / timing.count, 1e3 * timing.runs / timing.count);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Evaluates parameter sets of the diffusion controller in one process (load once, "
      "Reset per run), printing each set's fitness from the loop functions' metrics."};
  std::string file, controller = "dc";
  int sets = 20, trials = 2, threads = 1;
  double seconds = 60;
  app.add_option("experiment", file,
                 "an experiment with a diffusion controller and the diffusion_metrics loop "
                 "functions (e.g. experiments/diffusion.xml)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--controller", controller, "the id of the diffusion controller configuration")
      ->capture_default_str();
  app.add_option("--sets", sets, "parameter sets to evaluate")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  app.add_option("--trials", trials, "runs per set (seeds 1, 2, ...); its fitness is their mean")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  app.add_option("--seconds", seconds, "simulated seconds per run")
      ->check(CLI::Range(0.1, 1e6))
      ->capture_default_str();
  app.add_option("--threads", threads, "threads stepping the simulation")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "colony_evolution: %s (see --help)\n", e.what());
    return 2;
  }
  try {
    return Run(file, controller, sets, trials, seconds, threads);
  } catch (const colony::ConfigError& e) {
    std::fprintf(stderr, "colony_evolution: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "colony_evolution: %s\n", e.what());
    return 1;
  }
}
