// colony: the command line program.
//   colony run FILE.xml [--threads N] [--seed S] [--set PATH=VALUE]... [--out DIR] [--overwrite]
//              [--quiet] [--frames DIR] [--video FILE.mp4]
//   colony query [KIND|NAME]
//   colony sweep FILE.xml [--param PATH=V1,V2,...]... [--seeds A..B] ...  (apps/colony/sweep.h)
//   colony version
// Exit status: 0 success, 2 bad input (file or command line), 1 failure while running,
// 128 + N after signal N (SIGINT 130, SIGTERM 143, SIGHUP 129: the run stops after
// the current tick and says so in summary.json; a crash ends with the signal itself).
#include <dirent.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "apps/colony/sweep.h"
#include "core/crash_report.h"
#include "core/image_renderer.h"
#include "core/log.h"
#include "core/output.h"
#include "core/plugin_loader.h"
#include "core/registry.h"
#include "core/simulation.h"
#include "core/text.h"

namespace {

using colony::ConfigError;

constexpr const char* kUsage =
    "usage:\n"
    "  colony run FILE.xml [--threads N] [--seed S] [--set PATH=VALUE]... [--out DIR] "
    "[--overwrite]\n"
    "             [--quiet] [--frames DIR] [--video FILE.mp4]\n"
    "  colony query [KIND|NAME]      list plugins (kinds: entity, engine, physics_model, sensor,\n"
    "                                actuator, medium, renderer, controller, loop_functions)\n"
    "  colony sweep FILE.xml [--param PATH=V1,V2,...]... [--seeds 1..30] [--jobs N] [--out DIR] "
    "...\n"
    "                                many runs over parameters and seeds (colony sweep --help)\n"
    "  colony version\n"
    "--set overrides an attribute: framework.experiment.length=10, "
    "arena.distribute.entity.quantity=50,\n"
    "  controllers.diffusion[dc].params.velocity=0.1 (name[id] picks an element by id)\n"
    "--frames DIR writes PNG frames there (the file's <visualization>, else a camera over the\n"
    "  arena); --video FILE.mp4 also assembles them with ffmpeg (frames then go to the run\n"
    "  folder's frames/ unless --frames is given)\n"
    "--out and --frames refuse a folder that is not empty; --overwrite replaces the files a run\n"
    "  writes there (experiment.xml, metrics.csv, hashes.csv, summary.json, frames/, *.png)\n"
    "Ctrl-C (SIGINT), SIGTERM and SIGHUP stop the run after the current tick: the results so far\n"
    "  are written and summary.json says \"completed\": false; exit status 128 + the signal\n";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

long long ParseWhole(const std::string& option, const std::string& text, long long min,
                     long long max) {
  long long v = 0;
  const std::string problem = colony::ParseWholeOption(option, text, min, max, v);
  if (!problem.empty()) throw UsageError(problem);
  return v;
}

// Progress bar on a terminal, redrawn at most ten times a second.
class Progress {
 public:
  explicit Progress(bool enabled) : enabled_(enabled) {}
  void Update(const colony::Simulation& sim) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::milliseconds(100) && !sim.Done()) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (sim.length_ticks() == 0) {
      std::fprintf(stderr, "\r  tick %llu  %.1f s simulated  %.1f s elapsed ",
                   static_cast<unsigned long long>(sim.tick()), sim.time(), elapsed);
      return;
    }
    const double f = static_cast<double>(sim.tick()) / sim.length_ticks();
    const int width = 30, filled = static_cast<int>(f * width);
    std::string bar(filled, '=');
    if (filled < width) bar += '>' + std::string(width - filled - 1, ' ');
    const double left = f > 0 ? elapsed * (1 - f) / f : 0;
    std::fprintf(stderr, "\r  [%s] %3.0f%%  tick %llu/%llu  %.1f s elapsed, %.1f s left ",
                 bar.c_str(), 100 * f, static_cast<unsigned long long>(sim.tick()),
                 static_cast<unsigned long long>(sim.length_ticks()), elapsed, left);
  }
  void Finish() {
    if (enabled_) std::fprintf(stderr, "\n");
  }

 private:
  bool enabled_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_{};
};

// Runs ffmpeg over each camera's frames: `video` itself for one camera,
// NAME_CAMERA.EXT for several. Returns the files made.
std::vector<std::string> MakeVideos(const std::vector<colony::FrameSeries>& series,
                                    const std::string& video) {
  std::vector<std::string> made;
  for (const auto& s : series) {
    if (s.frames == 0) throw colony::RuntimeFailure("--video: no frames were drawn");
    const std::filesystem::path v(video);
    const std::string name = v.stem().string() + "_" + s.camera + v.extension().string();
    const std::string out = series.size() == 1 ? video : (v.parent_path() / name).string();
    char fps[32];
    std::snprintf(fps, sizeof fps, "%.6g", s.frames_per_second);
    std::vector<std::string> words = {
        "ffmpeg",     "-y",
        "-loglevel",  "error",
        "-framerate", fps,
        "-i",         s.pattern,
        "-vf",        "pad=ceil(iw/2)*2:ceil(ih/2)*2",  // H.264 players want even sizes
        "-pix_fmt",   "yuv420p",
        out};
    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    int status = 0;
    if (posix_spawnp(&pid, "ffmpeg", nullptr, nullptr, argv.data(), environ) != 0 ||
        waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      throw colony::RuntimeFailure("ffmpeg failed to make '" + out + "' from " + s.pattern);
    }
    made.push_back(out);
  }
  return made;
}

int Run(const std::vector<std::string>& args) {
  colony::ExperimentOptions options;
  std::string out_dir, frames_dir, video;
  bool quiet = false, overwrite = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](const char* name) -> std::string {
      if (i + 1 >= args.size()) throw UsageError(std::string(name) + " needs a value");
      return args[++i];
    };
    if (a == "--threads") {
      options.threads = static_cast<int>(ParseWhole("--threads", value("--threads"), 0, 256));
    } else if (a == "--seed") {
      options.seed = static_cast<uint64_t>(ParseWhole("--seed", value("--seed"), 0, INT64_MAX));
    } else if (a == "--set") {
      const std::string spec = value("--set");
      if (spec.find('=') == std::string::npos || spec.front() == '=') {
        throw UsageError("--set '" + spec +
                         "': expected PATH=VALUE, e.g. framework.experiment.length=10");
      }
      options.overrides.push_back(spec);
    } else if (a == "--out") {
      out_dir = value("--out");
      if (out_dir.empty()) throw UsageError("--out needs a folder");
    } else if (a == "--quiet") {
      quiet = true;
    } else if (a == "--overwrite") {
      overwrite = true;
    } else if (a == "--frames") {
      frames_dir = value("--frames");
      if (frames_dir.empty()) throw UsageError("--frames needs a folder");
    } else if (a == "--video") {
      video = value("--video");
      if (video.empty()) throw UsageError("--video needs a file name, e.g. run.mp4");
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError("unknown option '" + a + "'");
    } else if (options.file.empty()) {
      options.file = a;
    } else {
      throw UsageError("more than one experiment file given ('" + options.file + "' and '" + a +
                       "')");
    }
  }
  if (options.file.empty()) throw UsageError("colony run needs an experiment file");
  if (quiet) colony::SetLogLevel(colony::LogLevel::kError);
  // Decided before loading: a long run should not end without its frames or video.
  if ((!frames_dir.empty() || !video.empty()) && !colony::HaveImageRenderer()) {
    throw UsageError(colony::NoImageRendererMessage(frames_dir.empty() ? "--video" : "--frames"));
  }
  if (!video.empty() && !colony::OnPath("ffmpeg")) {
    throw UsageError(
        "--video needs ffmpeg, which is not installed (no 'ffmpeg' on the PATH); install it "
        "(Debian: apt-get install ffmpeg), or use --frames DIR and assemble the PNG frames "
        "elsewhere");
  }

  // Output folders are checked before loading: a long load should not end in
  // a refusal.
  try {
    if (!out_dir.empty())
      colony::PrepareOutputFolder(out_dir, "--out", overwrite, colony::RunFolderFiles());
    if (!frames_dir.empty())
      colony::PrepareOutputFolder(frames_dir, "--frames", overwrite, {"*.png"});
  } catch (const colony::OutputFolderInUse& e) {
    throw UsageError(e.what());
  }
  colony::InstallCrashHandlers();

  // The run folder is named before loading, so that loop functions know where
  // their own files go; it is created after.
  if (out_dir.empty()) out_dir = colony::FreshRunDir("runs", options.file);
  options.run_folder = out_dir;
  const auto t0 = std::chrono::steady_clock::now();
  auto sim = colony::Simulation::Load(options);
  if ((!frames_dir.empty() || !video.empty()) && sim->renderers().empty()) {
    sim->AddRenderer("<osmesa/>");  // a camera over the whole arena
  }
  if (!frames_dir.empty()) {
    for (const auto& r : sim->renderers()) r->set_output_dir(frames_dir);
  }
  const double load_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  colony::RunOutput output(out_dir, *sim);
  Progress progress(!quiet && isatty(STDERR_FILENO));
  colony::InstallStopHandlers();
  const auto summary = colony::RunToEnd(*sim, &output, load_seconds,
                                        [&](const colony::Simulation& s) { progress.Update(s); });
  progress.Finish();
  if (!summary.completed) {
    std::fprintf(stderr,
                 "colony: %s; results so far in %s/ (summary.json says \"completed\": false)\n",
                 summary.stop_reason.c_str(), output.dir().c_str());
    return 128 + colony::StopSignal();
  }
  if (!video.empty()) {
    std::vector<colony::FrameSeries> series;
    for (const auto& r : sim->renderers()) {
      for (auto& s : r->frame_series()) series.push_back(std::move(s));
    }
    for (const auto& file : MakeVideos(series, video)) {
      if (!quiet) std::printf("video %s\n", file.c_str());
    }
  }
  if (!quiet) {
    std::printf(
        "%llu ticks (%.1f s simulated) of %zu robots in %.2f s (%.3g robot-steps/s, %d thread%s)\n",
        static_cast<unsigned long long>(summary.ticks), summary.simulated_seconds, summary.robots,
        summary.wall_seconds, summary.robot_steps_per_second, summary.threads,
        summary.threads == 1 ? "" : "s");
    std::printf("final state hash %s\n",
                colony::StateHasher::Hex(summary.final_state_hash).c_str());
    std::printf("results in %s/ (experiment.xml, metrics.csv, summary.json)\n",
                output.dir().c_str());
  }
  return 0;
}

// Loads every library in the plugin search path, so query lists them too.
void LoadAllPlugins() {
  for (const auto& dir : colony::PluginSearchPath()) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
      if (entry.path().extension() != ".so") continue;
      const std::string error = colony::LoadPluginLibrary(entry.path().string(), "");
      if (!error.empty()) colony::LogWarning(error);
    }
  }
}

int Query(const std::vector<std::string>& args) {
  if (args.size() > 1) throw UsageError("colony query takes at most one KIND or NAME");
  LoadAllPlugins();
  const std::string filter = args.empty() ? "" : args[0];
  bool any = false;
  for (auto kind : colony::AllPluginKinds()) {
    const bool kind_match = filter == colony::PluginKindName(kind);
    bool header = false;
    for (const auto* p : colony::AllPlugins()) {
      if (p->kind != kind) continue;
      bool name_match = p->label == filter;
      for (const auto& a : p->aliases) name_match = name_match || a == filter;
      if (!filter.empty() && !kind_match && !name_match) continue;
      if (!header) {
        std::printf("%s%s:\n", any ? "\n" : "", colony::PluginKindName(kind));
        header = true;
      }
      any = true;
      std::printf("  %s", p->label.c_str());
      if (p->implementation != "default")
        std::printf(" (implementation=\"%s\")", p->implementation.c_str());
      for (const auto& a : p->aliases) std::printf(", alias %s", a.c_str());
      std::printf("\n      %s\n", p->summary.c_str());
      if (!p->library.empty()) std::printf("      library: %s\n", p->library.c_str());
      if (kind == colony::PluginKind::kPhysicsModel) {
        std::printf("      simulates: %s\n", p->components.empty()
                                                 ? "(no components)"
                                                 : colony::Join(p->components).c_str());
      }
      if (name_match || kind_match) {
        for (const auto& a : p->attributes) {
          std::printf("      %s = %s%s%s\n          %s\n", a.name.c_str(), a.accepted.c_str(),
                      a.default_value.empty() ? " (required)" : "  [default: ",
                      a.default_value.empty() ? "" : (a.default_value + "]").c_str(),
                      a.summary.c_str());
        }
      }
    }
  }
  if (!any) throw UsageError("no plugin kind or plugin named '" + filter + "'");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.empty() || args[0] == "help" || args[0] == "--help" || args[0] == "-h") {
      std::fputs(kUsage, args.empty() ? stderr : stdout);
      return args.empty() ? 2 : 0;
    }
    const std::string command = args[0];
    args.erase(args.begin());
    if (command == "run") return Run(args);
    if (command == "query") return Query(args);
    if (command == "sweep") return colony::sweep::SweepCommand(args);
    if (command == "version" || command == "--version") {
      std::printf("colony %s\n", COLONY_VERSION);
      return 0;
    }
    throw UsageError("unknown command '" + command + "'");
  } catch (const UsageError& e) {
    std::fprintf(stderr, "colony: %s\n%s", e.what(), kUsage);
    return 2;
  } catch (const ConfigError& e) {
    for (const auto& d : e.diagnostics())
      std::fprintf(stderr, "colony: error: %s\n", d.ToString().c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "\ncolony: run failed: %s\n", e.what());
    return 1;
  } catch (...) {
    std::fprintf(stderr,
                 "\ncolony: run failed: a plugin threw something that is not a std::exception\n");
    return 1;
  }
}
