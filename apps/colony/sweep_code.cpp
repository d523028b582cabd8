// The code a sweep's runs are made with: Colony's version and the SHA-256 of
// the program, of libcolony and of the plugin libraries the experiment
// loads. Only those files are recorded, not every library in the plugin
// folders: rebuilding a plugin the experiment does not use leaves its runs
// as they were, and a plugin found by name is recorded as the file the
// loader found (what the runs load too, since they search the same path).
#include <dlfcn.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "apps/colony/sweep.h"
#include "core/output.h"
#include "core/plugin_loader.h"
#include "core/run_files.h"

namespace colony::sweep {

namespace fs = std::filesystem;

namespace {

// Where the code of `address` was loaded from (libcolony for one of its
// functions).
std::string LibraryOf(const void* address) {
  Dl_info info{};
  if (dladdr(address, &info) == 0 || !info.dli_fname) return "";
  return fs::canonical(info.dli_fname).string();
}

std::string Short(const std::string& sha256) { return sha256.substr(0, 12) + "..."; }

}  // namespace

std::string Code::Fingerprint() const {
  std::vector<std::string> lines;
  for (const auto& f : files)
    lines.push_back(fs::path(f.path).filename().string() + " " + f.sha256);
  std::sort(lines.begin(), lines.end());
  return HashText("colony " + colony_version + "\n" + Join(lines, "\n"));
}

Code CurrentCode() {
  std::vector<std::string> paths = {
      fs::read_symlink("/proc/self/exe").string(),
      LibraryOf(reinterpret_cast<const void*>(&ColonyVersion)),
  };
  for (const auto& library : LoadedPluginLibraries()) paths.push_back(library.path);
  Code code;
  code.colony_version = ColonyVersion();
  std::sort(paths.begin(), paths.end());
  paths.erase(std::unique(paths.begin(), paths.end()), paths.end());
  for (const auto& path : paths) {
    if (path.empty()) continue;
    const std::string sha256 = FileSha256(path);
    if (sha256.empty()) throw Failure("cannot read " + path + " to record its SHA-256");
    code.files.push_back({path, sha256});
  }
  return code;
}

std::vector<std::string> CodeChanges(const Code& then, const Code& now) {
  std::vector<std::string> changes;
  if (then.colony_version != now.colony_version) {
    changes.push_back("Colony's version: " + then.colony_version + " then, " + now.colony_version +
                      " now");
  }
  // Files are matched by path, else by file name (a build tree moved).
  auto find = [](const std::vector<Code::File>& files, const Code::File& f) {
    auto it = std::find_if(files.begin(), files.end(),
                           [&](const Code::File& g) { return g.path == f.path; });
    if (it != files.end()) return it;
    return std::find_if(files.begin(), files.end(), [&](const Code::File& g) {
      return fs::path(g.path).filename() == fs::path(f.path).filename();
    });
  };
  for (const auto& f : then.files) {
    const auto match = find(now.files, f);
    if (match == now.files.end()) {
      changes.push_back(f.path + " is no longer loaded");
    } else if (match->sha256 != f.sha256) {
      changes.push_back(match->path + " has changed (SHA-256 " + Short(f.sha256) + " then, " +
                        Short(match->sha256) + " now)");
    }
  }
  for (const auto& f : now.files) {
    if (find(then.files, f) == then.files.end()) changes.push_back(f.path + " is newly loaded");
  }
  return changes;
}

}  // namespace colony::sweep
