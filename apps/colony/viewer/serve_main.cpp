// colony_serve: loads one experiment and serves it with the viewer
// (ServeRun), or runs it plainly, timing the ticks either way; for trying
// the viewer and measuring what serving costs (docs/viewer.md).
//   colony_serve FILE --serve 8080                      # open the printed URL
//   colony_serve FILE --plain                            # no server: the baseline
//   colony_serve FILE --serve 0 --play --exit-when-done  # served, nobody connected
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "apps/colony/viewer/viewer.h"
#include "core/crash_report.h"
#include "core/error.h"
#include "core/simulation.h"

int main(int argc, char** argv) {
  CLI::App app{"Serve one experiment with the live viewer, or run it plainly, and time it"};
  colony::ExperimentOptions experiment;
  std::string address;
  bool plain = false, play = false, exit_when_done = false;
  app.add_option("file", experiment.file, "experiment file")->required();
  app.add_option("--threads", experiment.threads, "threads (replaces <system threads>)");
  app.add_option("--set", experiment.overrides, "PATH=VALUE override, as colony run --set");
  app.add_option("--serve", address, "[HOST:]PORT to serve on (0: any free port)");
  app.add_flag("--plain", plain, "run without serving (the baseline)");
  app.add_flag("--play", play, "start playing as fast as possible instead of paused");
  app.add_flag("--exit-when-done", exit_when_done, "stop serving when the run is done");
  CLI11_PARSE(app, argc, argv);
  if (plain == !address.empty()) {
    std::fprintf(stderr, "colony_serve: give either --serve [HOST:]PORT or --plain\n");
    return 2;
  }
  colony::ServeOptions options;
  try {
    if (!plain) colony::ParseServeAddress(address, options);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "colony_serve: --serve %s\n", e.what());
    return 2;
  }
  try {
    auto sim = colony::Simulation::Load(experiment);
    colony::InstallStopHandlers();
    using Clock = std::chrono::steady_clock;
    // Timed from the end of the first tick (served, the run may wait for a
    // browser before it), in both modes alike.
    Clock::time_point first;
    double robot_steps = 0;
    uint64_t ticks = 0;
    std::atomic<bool> stop{false};
    auto count = [&](colony::Simulation& s) {
      if (ticks++ == 0)
        first = Clock::now();
      else
        robot_steps += static_cast<double>(s.robot_count());
      if (exit_when_done && s.Done()) stop = true;
    };
    int status = 0;
    if (plain) {
      while (!sim->Done() && !colony::StopSignal()) {
        sim->Step();
        count(*sim);
      }
    } else {
      options.start_playing = play;
      options.speed = play ? 0 : 1;
      options.stop = &stop;
      options.after_tick = count;
      status = colony::ServeRun(*sim, options);
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - first).count();
    std::printf("%llu ticks of %zu robots in %.3f s: %.4g robot-steps/s (%s)\n",
                static_cast<unsigned long long>(ticks), sim->robot_count(), seconds,
                robot_steps / seconds, plain ? "plain" : "served");
    return status;
  } catch (const colony::ConfigError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "colony_serve: %s\n", e.what());
    return 1;
  }
}
