#include "core/output.h"

#include <tinyxml2.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "core/crash_report.h"
#include "core/plugin_loader.h"
#include "core/table_writer.h"

#ifndef COLONY_VERSION
#define COLONY_VERSION "unknown"
#endif
#include "colony_git_revision.h"  // COLONY_GIT_REVISION (core/CMakeLists.txt)

namespace colony {

namespace fs = std::filesystem;

std::string RunSummary::ToJson() const {
  nlohmann::ordered_json j;
  j["completed"] = completed;
  if (!completed) j["stop_reason"] = stop_reason;
  j["ticks"] = ticks;
  j["simulated_seconds"] = simulated_seconds;
  j["wall_seconds"] = wall_seconds;
  j["step_seconds"] = step_seconds;
  j["robots"] = robots;
  j["threads"] = threads;
  j["seed"] = seed;
  j["robot_steps_per_second"] = robot_steps_per_second;
  j["final_state_hash"] = StateHasher::Hex(final_state_hash);
  auto& m = j["metrics"] = nlohmann::ordered_json::object();
  for (const auto& [name, value] : metrics) {
    // JSON has no NaN or infinity: such a metric is null.
    if (std::isfinite(value)) {
      m[name] = value;
    } else {
      m[name] = nullptr;
    }
  }
  j["colony_version"] = colony_version;
  j["git_revision"] = git_revision;
  j["command_line"] = command_line;
  auto& libraries = j["plugin_libraries"] = nlohmann::ordered_json::array();
  for (const auto& library : plugin_libraries)
    libraries.push_back({{"path", library.path}, {"sha256", library.sha256}});
  j["start_time"] = start_time;
  j["end_time"] = end_time;
  j["host"] = host;
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

const char* ColonyVersion() { return COLONY_VERSION; }
const char* ColonyGitRevision() { return COLONY_GIT_REVISION; }

std::vector<std::string> ProcessCommandLine() {
  std::ifstream file("/proc/self/cmdline", std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::vector<std::string> words;
  for (size_t start = 0; start < text.size();) {
    const size_t end = std::min(text.find('\0', start), text.size());
    words.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return words;
}

namespace {

// `when` as ISO 8601 in UTC: 2024-05-01T12:34:56Z.
std::string IsoUtc(std::chrono::system_clock::time_point when) {
  const std::time_t t = std::chrono::system_clock::to_time_t(when);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

std::string HostName() {
  char name[HOST_NAME_MAX + 1] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

// Prints an experiment document with each element, comment and declaration
// on the line it had in the file (the random stream of a <distribute> block
// is named by its line, so moving it would draw other places), the seed as
// random_seed and relative file names made absolute (ReproducibleXml).
class ReproducingPrinter : public tinyxml2::XMLPrinter {
 public:
  explicit ReproducingPrinter(const Simulation& sim)
      : tinyxml2::XMLPrinter(nullptr, /*compact=*/true),
        seed_(std::to_string(sim.seed())),
        base_(fs::path(sim.file()).parent_path().string()),
        libraries_(LoadedPluginLibraries()) {}

  bool VisitEnter(const tinyxml2::XMLElement& element,
                  const tinyxml2::XMLAttribute* attribute) override {
    SealElementIfJustOpened();
    MoveTo(element.GetLineNum());
    OpenElement(element.Name(), true);
    const tinyxml2::XMLElement* parent = element.Parent() ? element.Parent()->ToElement() : nullptr;
    // <framework><experiment>: the seed the run used, which --seed may have changed.
    const bool experiment = element.Name() == std::string("experiment") && parent &&
                            parent->Name() == std::string("framework");
    bool seeded = false;
    for (; attribute; attribute = attribute->Next()) {
      const std::string name = attribute->Name();
      if (experiment && name == "random_seed") {
        PushAttribute("random_seed", seed_.c_str());
        seeded = true;
        continue;
      }
      const std::string absolute = Absolute(name, attribute->Value());
      PushAttribute(name.c_str(), absolute.empty() ? attribute->Value() : absolute.c_str());
    }
    if (experiment && !seeded) PushAttribute("random_seed", seed_.c_str());
    return true;
  }
  bool Visit(const tinyxml2::XMLComment& comment) override {
    SealElementIfJustOpened();
    MoveTo(comment.GetLineNum());
    return tinyxml2::XMLPrinter::Visit(comment);
  }
  bool Visit(const tinyxml2::XMLDeclaration& declaration) override {
    MoveTo(declaration.GetLineNum());
    return tinyxml2::XMLPrinter::Visit(declaration);
  }
  bool VisitExit(const tinyxml2::XMLDocument& doc) override {
    Putc('\n');
    return tinyxml2::XMLPrinter::VisitExit(doc);
  }

 private:
  // Starts new lines until the next thing printed is on line `line`.
  void MoveTo(int line) {
    const char* text = CStr();
    const size_t size = CStrSize() > 0 ? static_cast<size_t>(CStrSize()) - 1 : 0;
    line_ += static_cast<int>(std::count(text + scanned_, text + size, '\n'));
    scanned_ = size;
    for (; line_ < line; ++line_, ++scanned_) Putc('\n');
  }

  // The absolute path attribute `name` = `value` stands for, or "": library=
  // as the loader resolved it (it tries the current folder, then the
  // experiment file's; a bare name is looked up in the plugin search path
  // and stays), another relative name of an existing file as its reader
  // looks for it (beside the experiment file, else from the current folder).
  std::string Absolute(const std::string& name, const std::string& value) const {
    if (name == "library") {
      if (value.find('/') == std::string::npos) return "";
      for (const auto& l : libraries_) {
        if (l.spec == value && l.base_dir == base_) return l.path;
      }
      return "";
    }
    // Only what reads as a file name: with a folder, or an extension with a
    // letter (not an id like "dc", nor a number like "0.5").
    const fs::path path(value);
    const std::string extension = path.extension().string();
    const bool file_like = value.find('/') != std::string::npos ||
                           std::any_of(extension.begin(), extension.end(), [](char c) {
                             return std::isalpha(static_cast<unsigned char>(c)) != 0;
                           });
    if (!file_like || path.is_absolute()) return "";
    std::error_code ec;
    for (const fs::path& p : {fs::path(base_) / value, fs::path(value)}) {
      if (fs::is_regular_file(p, ec)) return fs::absolute(p, ec).lexically_normal().string();
    }
    return "";
  }

  std::string seed_, base_;
  std::vector<LoadedLibrary> libraries_;
  int line_ = 1;        // the line being printed
  size_t scanned_ = 0;  // characters of the output counted into line_
};

}  // namespace

std::string ReproducibleXml(const Simulation& sim) {
  const tinyxml2::XMLDocument* doc = sim.document();
  if (!doc || !doc->RootElement()) return "";
  ReproducingPrinter printer(sim);
  doc->Accept(&printer);
  return printer.CStr();
}

std::string SummaryProblem(const std::string& json_text) {
  const auto j = nlohmann::json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded())
    return json_text.empty() ? "it is empty" : "it is not valid JSON (cut short?)";
  if (!j.is_object()) return "it is not a JSON object";
  struct Key {
    const char* name;
    bool (nlohmann::json::*is)() const noexcept;
  };
  for (const Key& k :
       {Key{"completed", &nlohmann::json::is_boolean}, Key{"ticks", &nlohmann::json::is_number},
        Key{"simulated_seconds", &nlohmann::json::is_number},
        Key{"wall_seconds", &nlohmann::json::is_number}, Key{"robots", &nlohmann::json::is_number},
        Key{"seed", &nlohmann::json::is_number},
        Key{"final_state_hash", &nlohmann::json::is_string},
        Key{"metrics", &nlohmann::json::is_object}}) {
    if (!j.contains(k.name)) return std::string("it has no \"") + k.name + "\"";
    if (!(j[k.name].*k.is)()) return std::string("its \"") + k.name + "\" has the wrong type";
  }
  if (!j["completed"].get<bool>()) {
    const auto reason = j.value("stop_reason", std::string());
    return "the run did not complete" + (reason.empty() ? std::string() : " (" + reason + ")");
  }
  return "";
}

std::string FreshRunDir(const std::string& root, const std::string& experiment_file) {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
  const std::string base =
      (fs::path(root) / (fs::path(experiment_file).stem().string() + "-" + stamp)).string();
  std::string dir = base;
  for (int k = 2; fs::exists(dir); ++k) dir = base + "-" + std::to_string(k);
  return dir;
}

const std::vector<std::string>& RunFolderFiles() {
  static const std::vector<std::string> files = {"experiment.xml",   "metrics.csv",
                                                 "hashes.csv",       "summary.json",
                                                 "trajectories.csv", "trajectories.csv.gz",
                                                 "trajectories.h5",  "experiment.xml.tmp",
                                                 "summary.json.tmp", "frames"};
  return files;
}

void PrepareOutputFolder(const std::string& dir, const std::string& what, bool overwrite,
                         const std::vector<std::string>& run_files) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw OutputFolderInUse(what + " '" + dir + "' is a file, not a folder");
  }
  if (fs::is_directory(dir, ec)) {
    std::vector<std::string> found;
    for (const auto& entry : fs::directory_iterator(dir, ec))
      found.push_back(entry.path().filename().string());
    std::sort(found.begin(), found.end());
    if (!found.empty() && !overwrite) {
      std::string list;
      for (size_t i = 0; i < found.size() && i < 5; ++i) list += (i ? ", " : "") + found[i];
      if (found.size() > 5) list += ", ... (" + std::to_string(found.size()) + " entries)";
      throw OutputFolderInUse(
          what + " '" + dir + "' is not empty (it holds " + list +
          "); give --overwrite to replace a previous run's files there, or choose "
          "another folder");
    }
    // --overwrite: remove only what a run writes.
    for (const auto& name : found) {
      const bool png = name.size() > 4 && name.compare(name.size() - 4, 4, ".png") == 0;
      const bool ours =
          std::find(run_files.begin(), run_files.end(), name) != run_files.end() ||
          (png && std::find(run_files.begin(), run_files.end(), "*.png") != run_files.end());
      if (!ours) continue;
      fs::remove_all(fs::path(dir) / name, ec);
      if (ec)
        throw RuntimeFailure("cannot remove '" + (fs::path(dir) / name).string() +
                             "': " + ec.message());
    }
  }
  fs::create_directories(dir, ec);
  if (ec) throw RuntimeFailure("cannot create the output folder '" + dir + "': " + ec.message());
}

RunOutput::RunOutput(std::string dir, Simulation& sim) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) throw RuntimeFailure("cannot create the output folder '" + dir_ + "': " + ec.message());
  // A previous run's summary must not pass for this run's result.
  fs::remove(fs::path(dir_) / "summary.json", ec);
  WriteFileAtomically((fs::path(dir_) / "experiment.xml").string(), ReproducibleXml(sim));
  metrics_ = std::make_unique<RowFile>((fs::path(dir_) / "metrics.csv").string());
  if (sim.output().hash_every > 0) {
    hashes_ = std::make_unique<RowFile>((fs::path(dir_) / "hashes.csv").string());
    hashes_->Append("tick,state_hash\n");
  }
  if (sim.output().trajectories_every > 0)
    trajectories_ = std::make_unique<Trajectories>(dir_, sim);
  row_.reserve(256);
  // The state before the first tick.
  Record(sim, true);
}

RunOutput::~RunOutput() = default;

void RunOutput::AfterTick(Simulation& sim, bool last) { Record(sim, last || sim.Done()); }

void RunOutput::Record(Simulation& sim, bool all) {
  const auto& out = sim.output();
  const uint64_t tick = sim.tick();
  char number[64];
  if (out.metrics_every > 0 && (tick % out.metrics_every == 0 || all)) {
    Metrics& m = sim.metrics();
    if (!header_written_) {
      m.Freeze();
      row_ = "tick,time";
      for (const auto& c : m.columns()) {
        row_ += ',';
        AppendCsvField(row_, c);
      }
      row_ += "\n";
      metrics_->Append(row_);
      header_written_ = true;
    }
    std::snprintf(number, sizeof number, "%llu,%.15g", static_cast<unsigned long long>(tick),
                  sim.time());
    row_ = number;
    // The shortest text that reads back as the same double, as summary.json
    // and results.csv have it.
    for (double v : m.values()) {
      row_ += ',';
      row_.append(number, std::to_chars(number, number + sizeof number, v).ptr);
    }
    row_ += '\n';
    metrics_->Append(row_);
  }
  if (hashes_ && (tick % out.hash_every == 0 || all)) {
    std::snprintf(number, sizeof number, "%llu,", static_cast<unsigned long long>(tick));
    row_ = number;
    row_ += StateHasher::Hex(sim.StateHash());
    row_ += '\n';
    hashes_->Append(row_);
  }
  if (trajectories_ && (tick % out.trajectories_every == 0 || all)) trajectories_->Record(sim);
}

void RunOutput::Finish(const RunSummary& summary) {
  metrics_->Close();
  if (hashes_) hashes_->Close();
  if (trajectories_) trajectories_->Close();
  if (!command_line_) {
    WriteFileAtomically((fs::path(dir_) / "summary.json").string(), summary.ToJson());
    return;
  }
  RunSummary s = summary;
  s.command_line = *command_line_;
  WriteFileAtomically((fs::path(dir_) / "summary.json").string(), s.ToJson());
}

namespace {

RunSummary Summarize(const Simulation& sim, double step_seconds, double robot_ticks,
                     double wall_seconds, std::chrono::system_clock::time_point start) {
  RunSummary s;
  s.ticks = sim.tick();
  s.simulated_seconds = sim.time();
  s.step_seconds = step_seconds;
  s.wall_seconds = wall_seconds;
  s.robots = sim.robot_count();
  s.threads = sim.threads();
  s.seed = sim.seed();
  s.robot_steps_per_second = step_seconds > 0 ? robot_ticks / step_seconds : 0;
  s.final_state_hash = sim.StateHash();
  const auto& m = sim.metrics();
  for (size_t i = 0; i < m.columns().size(); ++i)
    s.metrics.emplace_back(m.columns()[i], m.values()[i]);
  s.colony_version = ColonyVersion();
  s.git_revision = ColonyGitRevision();
  s.command_line = ProcessCommandLine();
  for (const auto& library : LoadedPluginLibraries()) {
    const bool seen = std::any_of(s.plugin_libraries.begin(), s.plugin_libraries.end(),
                                  [&](const auto& l) { return l.path == library.path; });
    if (!seen) s.plugin_libraries.push_back({library.path, library.sha256});
  }
  s.start_time = IsoUtc(start);
  s.end_time = IsoUtc(std::chrono::system_clock::now());
  s.host = HostName();
  return s;
}

}  // namespace

RunSummary RunToEnd(Simulation& sim, RunOutput* out, double load_seconds,
                    const std::function<void(const Simulation&)>& progress) {
  using Clock = std::chrono::steady_clock;
  double step_seconds = 0;
  double robot_ticks = 0;
  const auto start = Clock::now();
  // When loading began, on the calendar.
  const auto started = std::chrono::system_clock::now() -
                       std::chrono::duration_cast<std::chrono::system_clock::duration>(
                           std::chrono::duration<double>(load_seconds));
  auto wall = [&] {
    return load_seconds + std::chrono::duration<double>(Clock::now() - start).count();
  };
  std::string stop_reason;
  try {
    // Renderers draw the initial state, then every tick's, between steps.
    for (const auto& r : sim.renderers()) {
      if (out && r->output_dir().empty()) {
        r->set_output_dir((fs::path(out->dir()) / "frames").string());
      }
      r->AfterTick();
    }
    while (!sim.Done()) {
      const auto t0 = Clock::now();
      sim.Step();
      step_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
      robot_ticks += static_cast<double>(sim.robot_count());
      // An interrupt makes this tick the last: its rows are written.
      const int signal_number = StopSignal();
      if (out) out->AfterTick(sim, signal_number != 0);
      for (const auto& r : sim.renderers()) r->AfterTick();
      if (progress) progress(sim);
      if (signal_number) {
        stop_reason = std::string("interrupted by ") + SignalName(signal_number) + " after tick " +
                      std::to_string(sim.tick());
        break;
      }
    }
    for (const auto& r : sim.renderers()) r->Finish();
  } catch (const std::exception& e) {
    // What is known is kept, marked incomplete; the error goes on up.
    if (out) {
      RunSummary s = Summarize(sim, step_seconds, robot_ticks, wall(), started);
      s.completed = false;
      s.stop_reason = e.what();
      try {
        out->Finish(s);
      } catch (const std::exception&) {
        // The first error is the one to report.
      }
    }
    throw;
  }
  RunSummary s = Summarize(sim, step_seconds, robot_ticks, wall(), started);
  s.completed = stop_reason.empty();
  s.stop_reason = stop_reason;
  if (out) out->Finish(s);
  return s;
}

}  // namespace colony
