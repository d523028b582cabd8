#include "core/output.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/crash_report.h"

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
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
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
  static const std::vector<std::string> files = {
      "experiment.xml",     "metrics.csv",      "hashes.csv", "summary.json",
      "experiment.xml.tmp", "summary.json.tmp", "frames"};
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

RunOutput::RunOutput(std::string dir, const Simulation& sim) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) throw RuntimeFailure("cannot create the output folder '" + dir_ + "': " + ec.message());
  // A previous run's summary must not pass for this run's result.
  fs::remove(fs::path(dir_) / "summary.json", ec);
  WriteFileAtomically((fs::path(dir_) / "experiment.xml").string(), sim.ResolvedXml());
  metrics_ = std::make_unique<RowFile>((fs::path(dir_) / "metrics.csv").string());
  if (sim.output().hash_every > 0) {
    hashes_ = std::make_unique<RowFile>((fs::path(dir_) / "hashes.csv").string());
    hashes_->Append("tick,state_hash\n");
  }
  row_.reserve(256);
}

void RunOutput::AfterTick(Simulation& sim, bool last) {
  const auto& out = sim.output();
  last = last || sim.Done();
  char number[64];
  if (out.metrics_every > 0 && (sim.tick() % out.metrics_every == 0 || last)) {
    Metrics& m = sim.metrics();
    if (!header_written_) {
      m.Freeze();
      row_ = "tick,time";
      for (const auto& c : m.columns()) row_ += "," + c;
      row_ += "\n";
      metrics_->Append(row_);
      header_written_ = true;
    }
    std::snprintf(number, sizeof number, "%llu,%.6g", static_cast<unsigned long long>(sim.tick()),
                  sim.time());
    row_ = number;
    for (double v : m.values()) {
      std::snprintf(number, sizeof number, ",%.10g", v);
      row_ += number;
    }
    row_ += '\n';
    metrics_->Append(row_);
  }
  if (hashes_ && (sim.tick() % out.hash_every == 0 || last)) {
    std::snprintf(number, sizeof number, "%llu,", static_cast<unsigned long long>(sim.tick()));
    row_ = number;
    row_ += StateHasher::Hex(sim.StateHash());
    row_ += '\n';
    hashes_->Append(row_);
  }
}

void RunOutput::Finish(const RunSummary& summary) {
  metrics_->Close();
  if (hashes_) hashes_->Close();
  WriteFileAtomically((fs::path(dir_) / "summary.json").string(), summary.ToJson());
}

namespace {

RunSummary Summarize(const Simulation& sim, double step_seconds, double robot_ticks,
                     double wall_seconds) {
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
  return s;
}

}  // namespace

RunSummary RunToEnd(Simulation& sim, RunOutput* out, double load_seconds,
                    const std::function<void(const Simulation&)>& progress) {
  using Clock = std::chrono::steady_clock;
  double step_seconds = 0;
  double robot_ticks = 0;
  const auto start = Clock::now();
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
      RunSummary s = Summarize(sim, step_seconds, robot_ticks, wall());
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
  RunSummary s = Summarize(sim, step_seconds, robot_ticks, wall());
  s.completed = stop_reason.empty();
  s.stop_reason = stop_reason;
  if (out) out->Finish(s);
  return s;
}

}  // namespace colony
