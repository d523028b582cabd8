// What a served page shows and steps through, for the viewer's server
// (viewer.cpp): the live run (ServeRun steps the simulation) or a replay of a
// recorded one (ServeReplay, view_command.cpp, puts the recorded poses into
// a simulation loaded and never stepped). The server draws the scene and
// the frames from the simulation's space either way; the source says which
// tick that is and how to go to the next one.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "apps/colony/viewer/viewer.h"

namespace colony {

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // The tick shown, and the one a step goes to.
  virtual uint64_t tick() const = 0;
  virtual uint64_t next_tick() const = 0;
  // Nothing more to step to.
  virtual bool Done() const = 0;
  // To next_tick(), on the server's simulation thread.
  virtual void Step() = 0;
  // Back to the start; what it throws is the asking page's error.
  virtual void Reset(std::optional<uint64_t> seed) = 0;
  // Why the page's `command` ("inspect", "move") is refused whatever it
  // names, or "" when it is not.
  virtual std::string Refuses(const std::string& /*command*/) const { return ""; }
  // The scene's "replay" field.
  virtual bool replay() const { return false; }
};

// Serves `sim` as `source` shows and steps it (ServeRun's work, which see).
int ServeFrames(Simulation& sim, FrameSource& source, const ServeOptions& options);

}  // namespace colony
