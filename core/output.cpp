#include "core/output.h"

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace colony {

namespace fs = std::filesystem;

static std::string JsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

static std::string JsonString(const std::string& v) {
  std::string out = "\"";
  for (char c : v) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      out += buffer;
      continue;
    }
    out += c;
  }
  return out + "\"";
}

std::string RunSummary::ToJson() const {
  std::ostringstream s;
  s << "{\n"
    << "  \"ticks\": " << ticks << ",\n"
    << "  \"simulated_seconds\": " << JsonNumber(simulated_seconds) << ",\n"
    << "  \"wall_seconds\": " << JsonNumber(wall_seconds) << ",\n"
    << "  \"step_seconds\": " << JsonNumber(step_seconds) << ",\n"
    << "  \"robots\": " << robots << ",\n"
    << "  \"threads\": " << threads << ",\n"
    << "  \"seed\": " << seed << ",\n"
    << "  \"robot_steps_per_second\": " << JsonNumber(robot_steps_per_second) << ",\n"
    << "  \"final_state_hash\": \"" << StateHasher::Hex(final_state_hash) << "\",\n"
    << "  \"metrics\": {";
  for (size_t i = 0; i < metrics.size(); ++i) {
    s << (i ? ", " : "") << JsonString(metrics[i].first) << ": " << JsonNumber(metrics[i].second);
  }
  s << "}\n}\n";
  return s.str();
}

std::string FreshRunDir(const std::string& root, const std::string& experiment_file) {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
  const std::string base = (fs::path(root) / (fs::path(experiment_file).stem().string() + "-" + stamp)).string();
  std::string dir = base;
  for (int k = 2; fs::exists(dir); ++k) dir = base + "-" + std::to_string(k);
  return dir;
}

RunOutput::RunOutput(std::string dir, const Simulation& sim) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) throw RuntimeFailure("cannot create the output folder '" + dir_ + "': " + ec.message());
  // A previous run's summary must not pass for this run's result.
  fs::remove(fs::path(dir_) / "summary.json", ec);
  std::ofstream xml(fs::path(dir_) / "experiment.xml");
  xml << sim.ResolvedXml();
  if (!xml) throw RuntimeFailure("cannot write '" + dir_ + "/experiment.xml'");
  metrics_ = std::fopen((fs::path(dir_) / "metrics.csv").c_str(), "w");
  if (!metrics_) throw RuntimeFailure("cannot write '" + dir_ + "/metrics.csv'");
  if (sim.output().hash_every > 0) {
    hashes_ = std::fopen((fs::path(dir_) / "hashes.csv").c_str(), "w");
    if (!hashes_) throw RuntimeFailure("cannot write '" + dir_ + "/hashes.csv'");
    std::fprintf(hashes_, "tick,state_hash\n");
  }
}

RunOutput::~RunOutput() {
  if (metrics_) std::fclose(metrics_);
  if (hashes_) std::fclose(hashes_);
}

void RunOutput::AfterTick(Simulation& sim) {
  const auto& out = sim.output();
  if (out.metrics_every > 0 && (sim.tick() % out.metrics_every == 0 || sim.Done())) {
    Metrics& m = sim.metrics();
    if (!header_written_) {
      m.Freeze();
      std::fprintf(metrics_, "tick,time");
      for (const auto& c : m.columns()) std::fprintf(metrics_, ",%s", c.c_str());
      std::fprintf(metrics_, "\n");
      header_written_ = true;
    }
    std::fprintf(metrics_, "%llu,%.6g", static_cast<unsigned long long>(sim.tick()), sim.time());
    for (double v : m.values()) std::fprintf(metrics_, ",%.10g", v);
    std::fprintf(metrics_, "\n");
  }
  if (hashes_ && (sim.tick() % out.hash_every == 0 || sim.Done())) {
    std::fprintf(hashes_, "%llu,%s\n", static_cast<unsigned long long>(sim.tick()),
                 StateHasher::Hex(sim.StateHash()).c_str());
  }
}

void RunOutput::Finish(const RunSummary& summary) {
  std::fflush(metrics_);
  if (hashes_) std::fflush(hashes_);
  const fs::path tmp = fs::path(dir_) / "summary.json.tmp";
  {
    std::ofstream f(tmp);
    f << summary.ToJson();
    if (!f) throw RuntimeFailure("cannot write '" + tmp.string() + "'");
  }
  fs::rename(tmp, fs::path(dir_) / "summary.json");
}

RunSummary RunToEnd(Simulation& sim, RunOutput* out, double load_seconds,
                    const std::function<void(const Simulation&)>& progress) {
  using Clock = std::chrono::steady_clock;
  double step_seconds = 0;
  double robot_ticks = 0;
  const auto start = Clock::now();
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
    if (out) out->AfterTick(sim);
    for (const auto& r : sim.renderers()) r->AfterTick();
    if (progress) progress(sim);
  }
  for (const auto& r : sim.renderers()) r->Finish();
  RunSummary s;
  s.ticks = sim.tick();
  s.simulated_seconds = sim.time();
  s.step_seconds = step_seconds;
  s.wall_seconds = load_seconds + std::chrono::duration<double>(Clock::now() - start).count();
  s.robots = sim.robot_count();
  s.threads = sim.threads();
  s.seed = sim.seed();
  s.robot_steps_per_second = step_seconds > 0 ? robot_ticks / step_seconds : 0;
  s.final_state_hash = sim.StateHash();
  const auto& m = sim.metrics();
  for (size_t i = 0; i < m.columns().size(); ++i) s.metrics.emplace_back(m.columns()[i], m.values()[i]);
  if (out) out->Finish(s);
  return s;
}

}  // namespace colony
