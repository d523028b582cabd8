// Loading controller and loop-function libraries with dlopen.
#pragma once

#include <string>
#include <vector>

namespace colony {

// Where libraries named without a path are looked for, in order:
// $COLONY_PLUGIN_PATH (colon-separated), then lib/colony beside the running
// program (the build tree and the install tree have the same layout), then
// the install prefix.
std::vector<std::string> PluginSearchPath();

// Loads `spec`: a path (absolute, or relative to the working directory or to
// `base_dir`, the experiment file's folder) or a bare name looked up as
// lib<name>.so in the search path. Returns an empty string on success, or a
// message saying every place tried and why it failed.
std::string LoadPluginLibrary(const std::string& spec, const std::string& base_dir);

// A library LoadPluginLibrary loaded: as it was named (`spec`, `base_dir`),
// the file it found (an absolute path) and the SHA-256 of that file's
// content when it was loaded (for a run's provenance, summary.json).
struct LoadedLibrary {
  std::string spec, base_dir;
  std::string path;
  std::string sha256;
};
// Every library loaded so far in this process, in load order (one entry per
// spec and base_dir).
std::vector<LoadedLibrary> LoadedPluginLibraries();

}  // namespace colony
