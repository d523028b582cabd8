// colony: the command line program (read with CLI11: apps/colony/command_line.h).
//   colony run FILE.xml [--threads N] [--seed S] [--set PATH=VALUE]... [--out DIR] [--overwrite]
//              [--quiet] [--log-level LEVEL] [--frames DIR] [--video FILE.mp4] [--serve
//              [HOST:]PORT]
//   colony query [KIND|NAME]
//   colony sweep FILE.xml [--param PATH=V1,V2,...]... [--seeds A..B] ...  (apps/colony/sweep.h)
//   colony plot FOLDER --metric NAME [--against PARAM] ...              (apps/colony/plot.cpp)
//   colony view RUN_FOLDER [--serve [HOST:]PORT] (apps/colony/viewer/view_command.cpp) colony
//   version
// `colony --help` and `colony COMMAND --help` describe each option.
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

#include "apps/colony/command_line.h"
#include "apps/colony/sweep.h"
#include "apps/colony/viewer/viewer.h"
#include "core/crash_report.h"
#include "core/image_renderer.h"
#include "core/log.h"
#include "core/output.h"
#include "core/plugin_loader.h"
#include "core/registry.h"
#include "core/simulation.h"
#include "core/text.h"

namespace {

namespace fs = std::filesystem;
using colony::ConfigError;
using colony::cli::UsageError;

// Progress bar on a terminal, redrawn at most ten times a second, on the
// log's status line (log lines from any thread are written above it).
class Progress {
 public:
  explicit Progress(bool enabled) : enabled_(enabled) {}
  void Update(const colony::Simulation& sim) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::milliseconds(100) && !sim.Done()) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    char line[256];
    if (sim.length_ticks() == 0) {
      std::snprintf(line, sizeof line, "  tick %llu  %.1f s simulated  %.1f s elapsed",
                    static_cast<unsigned long long>(sim.tick()), sim.time(), elapsed);
      colony::SetStatusLine(line);
      return;
    }
    const double f = static_cast<double>(sim.tick()) / sim.length_ticks();
    const int width = 30, filled = static_cast<int>(f * width);
    std::string bar(filled, '=');
    if (filled < width) bar += '>' + std::string(width - filled - 1, ' ');
    const double left = f > 0 ? elapsed * (1 - f) / f : 0;
    std::snprintf(line, sizeof line, "  [%s] %3.0f%%  tick %llu/%llu  %.1f s elapsed, %.1f s left",
                  bar.c_str(), 100 * f, static_cast<unsigned long long>(sim.tick()),
                  static_cast<unsigned long long>(sim.length_ticks()), elapsed, left);
    colony::SetStatusLine(line);
  }
  // Ends the bar's line, so what follows starts on a line of its own.
  void Finish() {
    if (enabled_) colony::FinishStatusLine();
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

// `colony run`: its command line, as CLI11 fills it; values are checked
// by Run.
struct RunCommand {
  CLI::App* app = nullptr;
  std::string file, threads, seed, log_level = "info", out_dir, frames_dir, video, serve;
  std::vector<std::string> overrides;
  bool quiet = false, overwrite = false;
  CLI::Option *out_option = nullptr, *frames_option = nullptr, *video_option = nullptr,
              *serve_option = nullptr;

  explicit RunCommand(CLI::App& parent) {
    app = parent.add_subcommand("run", "run one experiment");
    app->allow_extras();
    app->add_option("FILE", file, "the experiment file (Colony's XML, or an ARGoS .argos file)")
        ->type_name("FILE.xml");
    app->add_option("--threads", threads,
                    "threads, 0 to 256 (replaces the file's <system threads>; 0 and 1 both mean "
                    "the calling thread only)")
        ->type_name("N");
    app->add_option("--seed", seed,
                    "random seed, a whole number >= 0 (replaces <experiment random_seed>)")
        ->type_name("S");
    colony::cli::AddListOption(
        *app, "--set", overrides,
        "overrides an attribute; repeatable: framework.experiment.length=10, "
        "arena.distribute.entity.quantity=50, controllers.diffusion[dc].params.velocity=0.1 "
        "(name[id] picks an element by id)")
        ->type_name("PATH=VALUE");
    out_option = app->add_option("--out", out_dir,
                                 "the run folder (default: a fresh runs/NAME-DATE-TIME); refused "
                                 "when not empty, unless --overwrite")
                     ->type_name("DIR");
    app->add_flag("--overwrite", overwrite,
                  "reuse a non-empty --out or --frames folder: the files a run writes there "
                  "(experiment.xml, metrics.csv, hashes.csv, trajectories.*, summary.json, "
                  "run.log, frames/, *.png) are replaced, anything else is left alone");
    app->add_flag("--quiet", quiet,
                  "prints only errors: hides warnings too, and the progress bar and closing "
                  "lines; run.log still gets every line of --log-level");
    app->add_option("--log-level", log_level,
                    "what is logged, on the terminal and in the run folder's run.log: error, "
                    "warning, info (the default) or debug")
        ->type_name("LEVEL");
    frames_option = app->add_option("--frames", frames_dir,
                                    "writes PNG frames into DIR (the file's <visualization>, "
                                    "else a camera over the whole arena); refused when DIR is "
                                    "not empty, unless --overwrite")
                        ->type_name("DIR");
    video_option = app->add_option("--video", video,
                                   "also assembles the frames into a video with ffmpeg (frames "
                                   "then go to the run folder's frames/ unless --frames is given)")
                       ->type_name("FILE.mp4");
    serve_option = app->add_option("--serve", serve,
                                   "serves the run, paused at tick 0, to the live viewer in a "
                                   "browser (docs/viewer.md): PORT on 127.0.0.1, or HOST:PORT; "
                                   "a served run writes no run folder")
                       ->type_name("[HOST:]PORT");
    app->footer(
        "Each log line says its level, and its tick and robot where there is one:\n"
        "  colony: warning: [tick 120] [mb3] ...\n"
        "The run folder receives experiment.xml (as resolved), metrics.csv, hashes.csv (with\n"
        "<output hash_every>), run.log and, last, summary.json.\n"
        "Ctrl-C (SIGINT), SIGTERM and SIGHUP stop the run after the current tick: the results so\n"
        "far are written and summary.json says \"completed\": false; exit status 128 + the "
        "signal.");
  }

  // The command line as options for loading; throws UsageError.
  colony::ExperimentOptions Check() {
    colony::ExperimentOptions options;
    if (file.empty()) throw UsageError("run needs an experiment file: colony run FILE.xml");
    for (const auto& extra : app->remaining()) {
      throw UsageError("more than one experiment file given ('" + file + "' and '" + extra + "')");
    }
    options.file = file;
    if (app->count("--threads"))
      options.threads = static_cast<int>(colony::cli::ParseWhole("--threads", threads, 0, 256));
    if (app->count("--seed"))
      options.seed = static_cast<uint64_t>(colony::cli::ParseWhole("--seed", seed, 0, INT64_MAX));
    for (const auto& spec : overrides) {
      if (spec.find('=') == std::string::npos || spec.front() == '=') {
        throw UsageError("--set '" + spec +
                         "': expected PATH=VALUE, e.g. framework.experiment.length=10");
      }
    }
    options.overrides = overrides;
    if (out_option->count() && out_dir.empty()) throw UsageError("--out needs a folder");
    if (frames_option->count() && frames_dir.empty()) throw UsageError("--frames needs a folder");
    if (video_option->count() && video.empty())
      throw UsageError("--video needs a file name, e.g. run.mp4");
    if (serve_option->count()) {
      // Steered by hand (pause, step, reset), a served run is not recorded.
      for (const auto* other : {out_option, frames_option, video_option}) {
        if (other->count()) {
          throw UsageError("--serve and " + other->get_name() +
                           " do not go together: a served run writes no run folder or frames");
        }
      }
      colony::ServeOptions address;
      try {
        colony::ParseServeAddress(serve, address);
      } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--serve ") + e.what());
      }
    }
    return options;
  }

  colony::LogLevel Level() const {
    colony::LogLevel level{};
    if (colony::ParseLogLevel(log_level, level)) return level;
    const std::vector<std::string> names = {"error", "warning", "info", "debug"};
    const std::string guess = colony::DidYouMean(log_level, names);
    throw UsageError("--log-level: '" + log_level + "' is not accepted; expected " +
                     colony::Join(names) +
                     (guess.empty() ? "" : " (did you mean '" + guess + "'?)"));
  }
};

// The folders frames were written to (none when no frame was drawn).
std::vector<std::string> FrameFolders(const colony::Simulation& sim) {
  std::vector<std::string> folders;
  for (const auto& r : sim.renderers()) {
    for (const auto& s : r->frame_series()) {
      const std::string dir = fs::path(s.pattern).parent_path().string();
      if (s.frames > 0 && std::find(folders.begin(), folders.end(), dir) == folders.end())
        folders.push_back(dir);
    }
  }
  return folders;
}

// `colony run FILE --serve [HOST:]PORT`: the live viewer steers the run
// until the page's End run button or Ctrl-C.
int Serve(RunCommand& command, colony::ExperimentOptions& options,
          std::chrono::steady_clock::time_point load_started) {
  colony::ServeOptions serve;
  colony::ParseServeAddress(command.serve, serve);  // checked by Check()
  auto sim = colony::Simulation::Load(options);
  char seconds[32];
  std::snprintf(
      seconds, sizeof seconds, "%.3f",
      std::chrono::duration<double>(std::chrono::steady_clock::now() - load_started).count());
  colony::LogDebug("loaded " + options.file + " in " + seconds +
                   " s: " + std::to_string(sim->robot_count()) + " robots, seed " +
                   std::to_string(sim->seed()));
  colony::InstallStopHandlers();
  serve.on_listening = [&](const std::string& url) {
    std::printf("viewer: open %s in a browser (%zu robots, paused at tick %llu; Ctrl-C ends it)\n",
                url.c_str(), sim->robot_count(), static_cast<unsigned long long>(sim->tick()));
    std::fflush(stdout);
  };
  const int status = colony::ServeRun(*sim, serve);
  if (!command.quiet) {
    std::printf("served %llu ticks of %zu robots; final state hash %s\n",
                static_cast<unsigned long long>(sim->tick()), sim->robot_count(),
                colony::StateHasher::Hex(sim->StateHash()).c_str());
  }
  colony::CloseLogFile();
  return status;
}

int Run(RunCommand& command) {
  const auto load_started = std::chrono::steady_clock::now();
  colony::ExperimentOptions options = command.Check();
  const colony::LogLevel level = command.Level();
  const bool quiet = command.quiet, overwrite = command.overwrite;
  std::string out_dir = command.out_dir;
  const std::string frames_dir = command.frames_dir, video = command.video;
  colony::SetLogLevel(level);
  if (quiet) colony::SetTerminalLogLevel(colony::LogLevel::kError);
  // Lines logged before the run folder exists go to its run.log too.
  colony::HoldLogLines();
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
  const std::string log_file = "run.log";
  if (!out_dir.empty()) colony::OpenLogFile((fs::path(out_dir) / log_file).string());
  colony::InstallCrashHandlers();
  if (command.serve_option->count()) return Serve(command, options, load_started);

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
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.3f", load_seconds);
  colony::LogDebug("loaded " + options.file + " in " + seconds +
                   " s: " + std::to_string(sim->robot_count()) + " robots, seed " +
                   std::to_string(sim->seed()) + ", " + std::to_string(sim->threads()) +
                   " thread(s), " + std::to_string(sim->length_ticks()) + " ticks to run");
  colony::RunOutput output(out_dir, *sim);
  if (command.out_dir.empty()) colony::OpenLogFile((fs::path(output.dir()) / log_file).string());
  colony::LogDebug("run folder " + output.dir() + "/");
  Progress progress(!quiet && isatty(STDERR_FILENO));
  colony::InstallStopHandlers();
  // Lines logged outside plugin code carry the tick being computed, and
  // the last one once the run is done.
  colony::SetLogTick(sim->tick() + 1);
  const auto summary =
      colony::RunToEnd(*sim, &output, load_seconds, [&](const colony::Simulation& s) {
        colony::SetLogTick(s.Done() ? s.tick() : s.tick() + 1);
        progress.Update(s);
      });
  progress.Finish();
  colony::ClearLogTick();
  if (!summary.completed) {
    std::fprintf(stderr,
                 "colony: %s; results so far in %s/ (summary.json says \"completed\": false)\n",
                 summary.stop_reason.c_str(), output.dir().c_str());
    colony::CloseLogFile();
    return 128 + colony::StopSignal();
  }
  const std::vector<std::string> frame_folders = FrameFolders(*sim);
  if (!video.empty()) {
    std::vector<colony::FrameSeries> series;
    for (const auto& r : sim->renderers()) {
      for (auto& s : r->frame_series()) series.push_back(std::move(s));
    }
    for (const auto& file : MakeVideos(series, video)) {
      if (!quiet) std::printf("video %s\n", file.c_str());
    }
  }
  colony::LogDebug("final state hash " + colony::StateHasher::Hex(summary.final_state_hash));
  colony::CloseLogFile();
  if (!quiet) {
    std::printf(
        "%llu ticks (%.1f s simulated) of %zu robots in %.2f s (%.3g robot-steps/s, %d thread%s)\n",
        static_cast<unsigned long long>(summary.ticks), summary.simulated_seconds, summary.robots,
        summary.wall_seconds, summary.robot_steps_per_second, summary.threads,
        summary.threads == 1 ? "" : "s");
    std::printf("final state hash %s\n",
                colony::StateHasher::Hex(summary.final_state_hash).c_str());
    std::string frames;
    for (const auto& dir : frame_folders)
      frames += (frames.empty() ? "; frames in " : ", ") + dir + "/";
    std::printf("results in %s/ (experiment.xml, metrics.csv, summary.json, run.log)%s\n",
                output.dir().c_str(), frames.c_str());
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

// The registered names closest to `word`, at most three: "'proximity' or
// 'positioning'".
std::string ClosestPluginNames(const std::string& word) {
  std::vector<std::string> names;
  for (auto kind : colony::AllPluginKinds()) names.push_back(colony::PluginKindName(kind));
  for (const auto* p : colony::AllPlugins()) {
    names.push_back(p->label);
    for (const auto& a : p->aliases) names.push_back(a);
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  std::vector<std::string> found, left;
  // Names starting with `word`, then typos, then names holding it.
  for (const auto& n : names) (n.rfind(word, 0) == 0 ? found : left).push_back(n);
  while (found.size() < 3) {
    const std::string guess = colony::DidYouMean(word, left);
    if (guess.empty()) break;
    found.push_back(guess);
    left.erase(std::find(left.begin(), left.end(), guess));
  }
  for (const auto& n : left) {
    if (word.size() >= 3 && n.find(word) != std::string::npos) found.push_back(n);
  }
  if (found.size() > 3) found.resize(3);
  std::string text;
  for (size_t i = 0; i < found.size(); ++i)
    text += (i == 0 ? "'" : i + 1 == found.size() ? " or '" : ", '") + found[i] + "'";
  return text;
}

// A sensor's or actuator's control interface: what a controller includes,
// the class it asks for and the members it reads or calls.
void PrintControlInterface(const colony::PluginInfo& p) {
  const bool sensor = p.kind == colony::PluginKind::kSensor;
  if (!sensor && p.kind != colony::PluginKind::kActuator) return;
  const auto& device = p.control_interface;
  if (device.header.empty()) return;
  std::printf("      header: #include \"%s\"\n", device.header.c_str());
  std::printf("      class: %s, from Get%s<%s>(\"%s\")\n", device.cpp_class.c_str(),
              sensor ? "Sensor" : "Actuator", device.cpp_class.c_str(), p.label.c_str());
  std::printf("      a controller %s:\n", sensor ? "reads" : "calls");
  for (const auto& member : device.members) std::printf("        %s\n", member.c_str());
  std::printf("      XML attributes:%s\n", p.attributes.empty() ? " none" : "");
}

// The attributes every sensor takes (sampling, bus accounting) or every
// controller element takes (its rate), read by the core (docs/events.md).
void PrintTimingAttributes(bool sensor) {
  struct Attribute {
    const char *name, *accepted, *default_value, *summary;
  };
  static const Attribute kSensor[] = {
      {"period", "a number of seconds >= one tick", "every tick",
       "samples every period; the readings are held in between (docs/events.md)"},
      {"phase", "a number of seconds in [0, period), or random", "0",
       "when the first sample falls (with period)"},
      {"bus", "true, false", "false",
       "counts what reading it costs on the robot's bus: metric bus_bytes (sensors with a bus "
       "model: proximity)"},
  };
  static const Attribute kController[] = {
      {"rate", "a number of steps per second <= ticks_per_second", "every tick",
       "ControlStep is called at this rate (OnEvent whenever a watched sensor emits)"},
      {"phase", "a number of seconds in [0, 1 / rate), or random", "0",
       "when the first step falls (with rate)"},
  };
  std::printf("      %s:\n", sensor ? "every sensor's sampling and bus accounting"
                                    : "attributes of the controller's element");
  const auto print = [](const Attribute& a) {
    std::printf("      %s = %s  [default: %s]\n          %s\n", a.name, a.accepted, a.default_value,
                a.summary);
  };
  if (sensor) {
    for (const auto& a : kSensor) print(a);
  } else {
    for (const auto& a : kController) print(a);
  }
}

int Query(CLI::App& command, const std::string& filter) {
  if (!command.remaining().empty()) {
    throw UsageError("query takes at most one KIND or NAME ('" + filter + "' and '" +
                     command.remaining().front() + "' given)");
  }
  LoadAllPlugins();
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
        PrintControlInterface(*p);
        if (kind == colony::PluginKind::kController) {
          PrintTimingAttributes(false);
          std::printf("      parameters (<params> attributes):%s\n",
                      p->attributes.empty() ? " none declared" : "");
        }
        for (const auto& a : p->attributes) {
          const bool required = a.default_value.empty() && a.name != "*";
          std::printf("      %s = %s%s%s\n          %s\n", a.name.c_str(), a.accepted.c_str(),
                      required                  ? " (required)"
                      : a.default_value.empty() ? ""
                                                : "  [default: ",
                      a.default_value.empty() ? "" : (a.default_value + "]").c_str(),
                      a.summary.c_str());
        }
        if (kind == colony::PluginKind::kSensor) PrintTimingAttributes(true);
      }
    }
  }
  if (!any) {
    const std::string close = ClosestPluginNames(filter);
    throw UsageError("no plugin kind or plugin named '" + filter + "'" +
                     (close.empty() ? "" : "; did you mean " + close + "?") +
                     " ('colony query' lists them all)");
  }
  return 0;
}

// Prints a bad command line's message and where the usage is; returns 2.
int UsageFailure(const std::string& message, const std::string& command) {
  colony::FinishStatusLine();
  std::fprintf(stderr, "colony: %s\nrun 'colony%s --help' for usage\n", message.c_str(),
               command.empty() ? "" : (" " + command).c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  CLI::App app{"Colony: a multi-robot swarm simulator. Runs XML experiment files (ARGoS's too).",
               "colony"};
  colony::cli::SetUpHelp(app);
  app.allow_extras();
  app.set_version_flag("--version", std::string("colony ") + COLONY_VERSION,
                       "prints Colony's version");
  app.footer(
      "'colony COMMAND --help' describes a command's options.\n"
      "Exit status: 0 success, 2 bad input (experiment file or command line), 1 failure while\n"
      "running, 128 + N after signal N.");
  RunCommand run(app);
  CLI::App* query = app.add_subcommand(
      "query",
      "lists the plugins (kinds: entity, engine, physics_model, sensor, actuator, medium, "
      "renderer, controller, loop_functions), or one kind, or one plugin and its XML attributes");
  query->allow_extras();
  std::string query_filter;
  query->add_option("NAME", query_filter, "a plugin kind or a plugin's name")
      ->type_name("KIND|NAME");
  CLI::App* version = app.add_subcommand("version", "prints Colony's version");
  // Only listed here: colony sweep and colony plot read their own command lines.
  app.add_subcommand("sweep",
                     "many runs of an experiment over parameters and seeds, resumable, "
                     "summarized ('colony sweep --help')");
  app.add_subcommand("plot",
                     "draws a metric of a run or a sweep as PNG with gnuplot ('colony plot "
                     "--help')");
  app.add_subcommand("view",
                     "serves a replay of a finished run from its recorded trajectories to the "
                     "live viewer ('colony view --help')");

  // The command named, for "run 'colony COMMAND --help'".
  std::string command;
  if (!args.empty()) {
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      if (sub->get_name() == args[0]) command = args[0];
    }
  }
  try {
    if (args.empty()) {
      std::fputs(app.help().c_str(), stderr);
      return 2;
    }
    if (command == "sweep") return colony::sweep::SweepCommand({args.begin() + 1, args.end()});
    if (command == "plot") return colony::sweep::PlotCommand({args.begin() + 1, args.end()});
    if (command == "view") return colony::ViewCommand({args.begin() + 1, args.end()});
    // "colony help [COMMAND]", as "colony [COMMAND] --help".
    if (args[0] == "help") {
      args.erase(args.begin());
      if (args.size() > 1) throw UsageError("help takes at most one COMMAND");
      if (!args.empty() && args[0] == "sweep") return colony::sweep::SweepCommand({"--help"});
      if (!args.empty() && args[0] == "plot") return colony::sweep::PlotCommand({"--help"});
      if (!args.empty() && args[0] == "view") return colony::ViewCommand({"--help"});
      args.push_back("--help");
    }
    if (!colony::cli::Parse(app, args)) return 0;
    if (*run.app) return Run(run);
    if (*query) return Query(*query, query_filter);
    if (*version) {
      if (!version->remaining().empty())
        throw UsageError("version takes nothing, not '" + version->remaining()[0] + "'");
      std::printf("colony %s\n", COLONY_VERSION);
      return 0;
    }
    throw UsageError("no command given");
  } catch (const UsageError& e) {
    return UsageFailure(e.what(), command);
  } catch (const ConfigError& e) {
    colony::FinishStatusLine();
    for (const auto& d : e.diagnostics()) colony::LogError(d.ToString());
    return 2;
  } catch (const std::exception& e) {
    colony::FinishStatusLine();
    colony::LogError(std::string("run failed: ") + e.what());
    return 1;
  } catch (...) {
    colony::FinishStatusLine();
    colony::LogError("run failed: a plugin threw something that is not a std::exception");
    return 1;
  }
}
