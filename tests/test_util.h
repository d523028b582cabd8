// Helpers for tests that build small experiments from inline XML.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "core/image_renderer.h"
#include "core/registry.h"
#include "core/simulation.h"

namespace colony::testing {

// An experiment around `arena_body` (entities inside <arena>), with the given
// <controllers> content, in an arena of `size` centred on the origin.
inline std::string Experiment(const std::string& arena_body, const std::string& controllers = "",
                              const std::string& arena_size = "4,4,1",
                              const std::string& extra = "",
                              const std::string& engines = "<kinematics2d id=\"k2d\"/>") {
  return "<colony><framework><experiment length=\"10\" ticks_per_second=\"10\" "
         "random_seed=\"7\"/></framework>"
         "<controllers>" +
         controllers +
         "</controllers>"
         "<arena size=\"" +
         arena_size + "\" center=\"0,0,0.5\">" + arena_body +
         "</arena>"
         "<physics_engines>" +
         engines + "</physics_engines>" + extra + "</colony>";
}

inline std::unique_ptr<Simulation> LoadXml(const std::string& xml,
                                           std::vector<std::string> overrides = {},
                                           std::optional<int> threads = std::nullopt) {
  ExperimentOptions options;
  options.text = xml;
  options.overrides = std::move(overrides);
  options.threads = threads;
  return Simulation::Load(options);
}

// Whether this build has the physics engine `name` (-DCOLONY_WITH_DYNAMICS2D=OFF
// and -DCOLONY_WITH_DYNAMICS3D=OFF leave engines out).
inline bool HaveEngine(const std::string& name) {
  return Registry<PhysicsEngine>::Get().Find(name) != nullptr;
}

// An experiment file of experiments/ (e.g. "pushpull.xml") with `seed`.
inline std::unique_ptr<Simulation> LoadExperiment(const std::string& file, uint64_t seed,
                                                  std::vector<std::string> overrides = {},
                                                  std::optional<int> threads = std::nullopt) {
  ExperimentOptions options;
  options.file = std::string(COLONY_SOURCE_DIR) + "/experiments/" + file;
  options.seed = seed;
  options.threads = threads;
  options.overrides = std::move(overrides);
  return Simulation::Load(options);
}

// Steps `sim` for `seconds` of simulated time (rounded to whole ticks).
inline void RunFor(Simulation& sim, double seconds) {
  const int ticks = static_cast<int>(std::lround(seconds / sim.dt()));
  for (int t = 0; t < ticks; ++t) sim.Step();
}

// Where entity `id` is (its base's centre).
inline Vec3 PositionOf(const Simulation& sim, const std::string& id) {
  return sim.space().pose(sim.space().Find(id).index).position;
}

// The value of metric `name` as the loop functions last set it (NaN and a
// test failure if there is none).
inline double Metric(const Simulation& sim, const std::string& name) {
  auto& metrics = const_cast<Simulation&>(sim).metrics();
  const auto& columns = metrics.columns();
  const auto it = std::find(columns.begin(), columns.end(), name);
  if (it == columns.end()) {
    ADD_FAILURE() << "no metric '" << name << "'";
    return std::numeric_limits<double>::quiet_NaN();
  }
  return metrics.values()[static_cast<size_t>(it - columns.begin())];
}

// The message of the ConfigError loading `xml` raises, or "" if it loads.
inline std::string LoadError(const std::string& xml, std::vector<std::string> overrides = {}) {
  try {
    LoadXml(xml, std::move(overrides));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

// While it lives, this build has no image renderer, as one configured with
// -DCOLONY_WITH_OSMESA=OFF.
class WithoutImageRenderer {
 public:
  // The backend's plugin is loaded first, so that it cannot install itself
  // later, while this object says there is none.
  WithoutImageRenderer() : saved_((HaveImageRenderer(), SetImageRendererFactory(nullptr))) {}
  ~WithoutImageRenderer() { SetImageRendererFactory(saved_); }
  WithoutImageRenderer(const WithoutImageRenderer&) = delete;
  WithoutImageRenderer& operator=(const WithoutImageRenderer&) = delete;

 private:
  ImageRendererFactory saved_;
};

// What a shell command printed (standard output and error together) and its
// exit status (-1 when a signal ended it).
struct CommandResult {
  int status;
  std::string output;
};
inline CommandResult RunCommand(const std::string& command) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  std::string output;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

// The whole content of a file ("" if unreadable).
inline std::string ReadFile(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// An empty scratch folder name, unique to this test process (not created).
inline std::filesystem::path FreshTempDir(const std::string& prefix, const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   (prefix + "_" + name + "_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  return dir;
}

// Passes when `message` is an error containing each of `parts`.
inline ::testing::AssertionResult Mentions(const std::string& message,
                                           const std::vector<std::string>& parts) {
  if (message.empty())
    return ::testing::AssertionFailure() << "the experiment loaded without any error";
  for (const auto& part : parts) {
    if (message.find(part) == std::string::npos) {
      return ::testing::AssertionFailure() << "the message lacks \"" << part << "\":\n" << message;
    }
  }
  return ::testing::AssertionSuccess();
}

// Starts `argv` (argv[0] a path) in the background with its standard output
// and error going to `output` (created or truncated; "/dev/null" discards
// them). Returns its pid, or -1 if it could not be started.
inline pid_t SpawnWithOutput(std::vector<std::string> argv, const std::string& output) {
  std::vector<char*> words;
  for (auto& a : argv) words.push_back(a.data());
  words.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, output.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = -1;
  if (posix_spawn(&pid, words[0], &actions, nullptr, words.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

// The attribute names in the first column of the attribute tables of
// `folder`/README.md (rows starting "| `name` |"), in order.
inline std::vector<std::string> ReadmeAttributes(const std::string& folder) {
  const std::string text = ReadFile(std::string(COLONY_SOURCE_DIR) + "/" + folder + "/README.md");
  std::vector<std::string> names;
  const std::regex row(R"(\n\| `([a-z_]+)` \|)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), row); it != std::sregex_iterator();
       ++it) {
    names.push_back((*it)[1]);
  }
  return names;
}

}  // namespace colony::testing
