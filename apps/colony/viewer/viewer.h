// The live viewer (`colony run FILE --serve [HOST:]PORT`): serves a run over
// HTTP + WebSocket to a web page that draws it with three.js. The run
// starts paused; the page plays, pauses, steps it and sets its speed,
// inspects a robot (its sensors' readings, its actuators' last commands,
// its controller's values) and, while paused, moves robots and movable
// objects (Simulation::MoveEntity). The protocol (scene JSON once, binary
// frames, JSON commands) is in docs/viewer.md.
//
// Threads: the simulation is stepped only on the thread calling ServeRun;
// the network thread (ws_hub.h) parses and checks what browsers send and
// passes valid commands over a queue, and sends the snapshots the
// simulation thread encodes between ticks. A browser that stalls loses
// frames; it never slows the simulation.
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <vector>

namespace colony {

class Simulation;

struct ServeOptions {
  std::string host = "127.0.0.1";
  int port = 0;  // 0: any free port (the URL printed names it)
  // The access token the page and the WebSocket must carry (?token=..., or
  // the cookie the page's reply sets), printed as part of the URL. "": none
  // on a loopback address (127.0.0.1, ::1, localhost), a random one (128
  // bits) on any other; a token set here is required whatever the address.
  std::string token;
  // Frames per second of wall time sent while the run plays, at most.
  double updates_per_second = 10;
  // How the run starts: paused (the default, as `colony run --serve`), or
  // playing at `speed` times real time (0: as fast as possible).
  bool start_playing = false;
  double speed = 1;
  // Where the page's files are ("": share/colony/viewer next to the
  // program's folder, as plugins are found in lib/colony; see ViewerWebDir)
  // and three.js (Debian's libjs-three).
  std::string web_dir;
  std::string three_dir = "/usr/share/javascript/three";
  // Called after every tick, on the simulation thread (the host records its
  // output there: metrics rows, renderers).
  std::function<void(Simulation&)> after_tick;
  // Called once listening, with the page's URL (with its ?token=...); by default prints
  // "viewer: open http://HOST:PORT/ in a browser" to standard output.
  std::function<void(const std::string& url)> on_listening;
  // Set by another thread to end ServeRun (tests, embedding programs).
  const std::atomic<bool>* stop = nullptr;
};

// Reads "[HOST:]PORT" (e.g. "8080", "0.0.0.0:8080", "[::1]:8080") into
// `options`. Throws std::invalid_argument naming the bad text and what is
// accepted.
void ParseServeAddress(const std::string& text, ServeOptions& options);

// Where the page's files are installed: $COLONY_VIEWER_DIR if set, else
// ../share/colony/viewer from the program's folder, else the install prefix's.
std::string ViewerWebDir();

// Serves `sim`, paused at its current tick, until the page sends "quit",
// `options.stop` is set, or an interrupt arrives (core/crash_report.h:
// StopSignal, with the host's InstallStopHandlers). Returns 0, or 128 + the
// signal. When the run is done it stays on view until then. Throws
// RuntimeFailure when it cannot listen (address in use...) or the page's
// files are missing, and rethrows what a tick throws.
int ServeRun(Simulation& sim, const ServeOptions& options);

// Serves a replay of the run recorded in `run_folder` (`colony view`): the
// scene of its experiment.xml, loaded and never stepped, with the robots'
// poses of each recorded tick read from its trajectories table
// (trajectories.csv, .csv.gz or .h5; docs/data-output.md). Play, pause,
// step (to the next recorded tick), speed and reset go through the
// recorded ticks; inspect and move are refused. Returns as ServeRun.
// Throws ConfigError when the folder is not a run folder, has no
// trajectories, or its table is unreadable, cut short or names robots the
// experiment does not have; RuntimeFailure when it cannot listen.
int ServeReplay(const std::string& run_folder, const ServeOptions& options);

// `colony view RUN_FOLDER [--serve [HOST:]PORT]` (default 127.0.0.1:8080):
// `args` are the words after "view". Returns the exit status: 0, 2 for a
// bad command line or run folder (the message on standard error), 1 when it
// cannot serve, 128 + the signal that ended it.
int ViewCommand(const std::vector<std::string>& args);

}  // namespace colony
