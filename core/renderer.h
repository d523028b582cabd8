// Renderers (plugin kind "renderer"): the elements of <visualization>. A
// renderer draws the space; the host calls it from the main thread between
// ticks (once before the first tick, then after every tick), never during a
// step, so it only reads the space and cannot change the results.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/config.h"
#include "core/registry.h"
#include "core/simulation_bound.h"

namespace colony {

class Simulation;

// A numbered series of frames a renderer wrote: one per camera.
struct FrameSeries {
  std::string camera;
  std::string pattern;           // printf pattern of the files, e.g. "frames/top_%06d.png"
  uint64_t frames = 0;           // files 0 .. frames-1
  double frames_per_second = 0;  // of simulated time
};

class Renderer : public SimulationBound {
 public:
  virtual ~Renderer() = default;
  // Reads the renderer's element (attributes already checked against the
  // registered list). Called before the arena is built.
  virtual void Configure(const ConfigNode& node) = 0;
  // Draws what is due at the current tick. Throws ConfigError for a bad
  // setting only detectable once the arena exists, RuntimeFailure otherwise.
  virtual void AfterTick() = 0;
  // The run is over.
  virtual void Finish() {}
  virtual std::vector<FrameSeries> frame_series() const { return {}; }

  // Where frames go; set by the host before the first tick.
  void set_output_dir(std::string dir) { output_dir_ = std::move(dir); }
  const std::string& output_dir() const { return output_dir_; }

 private:
  std::string output_dir_;
};

// COLONY_REGISTER_RENDERER(MyRenderer, "label", "summary", {{"attribute", "accepted", "default",
// "doc"}});
#define COLONY_REGISTER_RENDERER(CLASS, LABEL, SUMMARY, ...)                                 \
  COLONY_REGISTER_PLUGIN_(::colony::Renderer, ::colony::PluginKind::kRenderer, CLASS, LABEL, \
                          "default", SUMMARY, __VA_ARGS__)

}  // namespace colony
