#include "core/plugin_loader.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "core/config.h"
#include "core/registry.h"
#include "core/run_files.h"

#ifndef COLONY_INSTALL_PLUGIN_DIR
#define COLONY_INSTALL_PLUGIN_DIR "/usr/local/lib/colony"
#endif

namespace colony {

namespace fs = std::filesystem;

namespace {

std::mutex loaded_mutex;
std::vector<LoadedLibrary> loaded;

}  // namespace

std::vector<std::string> PluginSearchPath() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("COLONY_PLUGIN_PATH")) {
    for (const auto& d : SplitList(env, ':'))
      if (!d.empty()) dirs.push_back(d);
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back((exe.parent_path().parent_path() / "lib" / "colony").string());
  dirs.push_back(COLONY_INSTALL_PLUGIN_DIR);
  // The same folder named twice is searched once.
  std::vector<std::string> unique;
  for (const auto& d : dirs) {
    const std::string canonical = fs::weakly_canonical(d, ec).string();
    bool seen = false;
    for (const auto& u : unique) seen = seen || fs::weakly_canonical(u, ec).string() == canonical;
    if (!seen) unique.push_back(d);
  }
  return unique;
}

std::string LoadPluginLibrary(const std::string& spec, const std::string& base_dir) {
  std::vector<std::string> candidates;
  const bool has_dir = spec.find('/') != std::string::npos;
  auto with_ext = [](const std::string& s) {
    return s.size() > 3 && s.compare(s.size() - 3, 3, ".so") == 0
               ? std::vector<std::string>{s}
               : std::vector<std::string>{s + ".so", s};
  };
  if (has_dir) {
    std::vector<std::string> bases = {spec};
    if (!fs::path(spec).is_absolute() && !base_dir.empty())
      bases.push_back((fs::path(base_dir) / spec).string());
    for (const auto& b : bases)
      for (const auto& c : with_ext(b)) candidates.push_back(c);
  } else {
    for (const auto& dir : PluginSearchPath()) {
      for (const auto& c : with_ext((fs::path(dir) / ("lib" + spec)).string()))
        candidates.push_back(c);
      for (const auto& c : with_ext((fs::path(dir) / spec).string())) candidates.push_back(c);
    }
  }
  std::string tried;
  for (const auto& c : candidates) {
    std::error_code ec;
    if (!fs::is_regular_file(c, ec)) {
      tried += "\n    " + c + " (no such file)";
      continue;
    }
    SetLoadingLibrary(c);
    void* handle = dlopen(fs::absolute(c).c_str(), RTLD_NOW | RTLD_GLOBAL);
    SetLoadingLibrary("");
    if (handle) {
      // Kept open: registered factories live in it.
      const std::lock_guard lock(loaded_mutex);
      const bool known = std::any_of(loaded.begin(), loaded.end(), [&](const LoadedLibrary& l) {
        return l.spec == spec && l.base_dir == base_dir;
      });
      if (!known) {
        const std::string path = fs::absolute(c).lexically_normal().string();
        loaded.push_back({spec, base_dir, path, FileSha256(path)});
      }
      return "";
    }
    tried += "\n    " + c + " (" + dlerror() + ")";
  }
  std::string message = "cannot load library '" + spec + "'; tried:" + tried;
  if (!has_dir) message += "\n    (set COLONY_PLUGIN_PATH to add folders to the search path)";
  return message;
}

std::vector<LoadedLibrary> LoadedPluginLibraries() {
  const std::lock_guard lock(loaded_mutex);
  return loaded;
}

}  // namespace colony
