// rab_bench: what range-and-bearing communication costs per robot and tick.
// Runs the same swarm twice, once driving only (baseline) and once also
// broadcasting and reading range-and-bearing messages every tick, and prints
// robot-steps per second of both (wall clock), CPU ns per robot-step of both
// and their difference (CPU time: robust to other programs sharing the machine).
//
//   rab_bench [--robots N] [--range R] [--area A] [--ticks T] [--threads K]
//             [--occlusions true|false] [--repeat K] [--only baseline|rab] [--cell C]
//             [--placement uniform|grid]
//
// Robots: marXbots placed at random on A square metres of floor per robot
// (default 0.5, as the diffusion benchmark scenes), kinematics2d, 10 ticks/s.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/range_and_bearing/range_and_bearing.h"
#include "core/registry.h"
#include "core/simulation.h"
#include "sensors/range_and_bearing/range_and_bearing.h"

namespace colony {
namespace {

// Drives in wide circles; with messages, sends its tick count and turns a
// little towards the mean bearing of what it hears (work a flocking
// controller would do on every packet).
class BenchController : public Controller {
 public:
  void Init(const Params& params) override {
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    try {
      rab_in_ = &GetSensor<RangeAndBearingSensor>("range_and_bearing");
      rab_out_ = &GetActuator<RangeAndBearingActuator>("range_and_bearing");
    } catch (const std::logic_error&) {
    }
  }
  void ControlStep() override {
    double turn = 0.02;
    if (rab_in_) {
      double sum = 0;
      for (const auto& p : rab_in_->packets()) sum += p.bearing * p.data[0];
      turn += 1e-6 * sum;
      rab_out_->SetByte(0, static_cast<uint8_t>(++ticks_));
      heard += rab_in_->packets().size();
    }
    wheels_->SetLinearVelocity(0.1 - turn, 0.1 + turn);
  }
  uint64_t heard = 0;

 private:
  DifferentialSteering* wheels_ = nullptr;
  const RangeAndBearingSensor* rab_in_ = nullptr;
  RangeAndBearingActuator* rab_out_ = nullptr;
  uint8_t ticks_ = 0;
};

COLONY_REGISTER_CONTROLLER(BenchController, "rab_bench_controller",
                           "rab_bench: drives, optionally talks");

struct Options {
  int robots = 10000;
  double range = 1.0;
  double area = 0.5;
  int ticks = 100;
  int threads = 2;
  bool occlusions = false;
  int repeat = 3;
  std::string only;   // "baseline" or "rab": run only that one (for profilers)
  double cell = 0;    // the medium's cell_size (0: its default)
  bool grid = false;  // robots on a square grid, created row by row (slot order = spatial order)
};

std::string Number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", v);
  return buffer;
}

std::string Scene(const Options& o, bool with_rab) {
  const double side = std::sqrt(o.area * o.robots);
  // Whole millimetres: <walls> writes its boxes with 6 decimals, and an
  // arena size with more would put them a hair outside the arena.
  const double arena = std::ceil((side + 0.2) * 1000) / 1000;
  const double half = side / 2 - 0.1;
  const std::string devices =
      with_rab ? "<sensors><range_and_bearing/></sensors><actuators><differential_steering/>"
                 "<range_and_bearing range=\"" +
                     std::to_string(o.range) + "\"/></actuators>"
               : "<actuators><differential_steering/></actuators>";
  const int per_row = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(o.robots))));
  const std::string spacing = std::to_string(std::sqrt(o.area));
  const std::string position =
      o.grid ? "<position method=\"grid\" center=\"0,0,0\" distances=\"" + spacing + "," + spacing +
                   ",0\" layout=\"" + std::to_string(per_row) + "," + std::to_string(per_row) +
                   ",1\"/>"
             : "<position method=\"uniform\" min=\"-" + std::to_string(half) + ",-" +
                   std::to_string(half) + ",0\" max=\"" + std::to_string(half) + "," +
                   std::to_string(half) + ",0\"/>";
  return "<colony><framework><system threads=\"" + std::to_string(o.threads) +
         "\"/><experiment length=\"100000\" ticks_per_second=\"10\" random_seed=\"1\"/></framework>"
         "<controllers><rab_bench_controller id=\"c\">" +
         devices +
         "</rab_bench_controller></controllers>"
         "<arena size=\"" +
         Number(arena) + "," + Number(arena) +
         ",1\" center=\"0,0,0.5\">"
         "<walls thickness=\"0.1\" height=\"0.5\"/><distribute>" +
         position +
         "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
         "<entity quantity=\"" +
         std::to_string(o.robots) +
         "\" max_trials=\"1000\"><marxbot id=\"mb\">"
         "<controller config=\"c\"/></marxbot></entity></distribute></arena>"
         "<physics_engines><kinematics2d id=\"k\"/></physics_engines>"
         "<media><range_and_bearing id=\"rab\" check_occlusions=\"" +
         (o.occlusions ? "true" : "false") + "\"" +
         (o.cell > 0 ? " cell_size=\"" + std::to_string(o.cell) + "\"" : std::string()) +
         "/></media>"
         "</colony>";
}

double CpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Timing {
  double wall = 0, cpu = 0;  // seconds spent stepping (medians over repetitions)
  double heard = 0;          // packets per robot-step
};

Timing Measure(const Options& o, bool with_rab) {
  std::vector<double> walls, cpus;
  Timing out;
  for (int r = 0; r < o.repeat; ++r) {
    ExperimentOptions options;
    options.text = Scene(o, with_rab);
    auto sim = Simulation::Load(options);
    sim->Step();  // warm-up: buffers reach their size
    const double c0 = CpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    for (int t = 0; t < o.ticks; ++t) sim->Step();
    walls.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    cpus.push_back(CpuSeconds() - c0);
    if (with_rab) {
      uint64_t total = 0;
      for (int i = 0; i < o.robots; ++i) {
        total += dynamic_cast<BenchController*>(
                     sim->ControllerOf(sim->space().Find("mb" + std::to_string(i))))
                     ->heard;
      }
      out.heard = static_cast<double>(total) / (static_cast<double>(o.robots) * (o.ticks + 1));
    }
  }
  std::sort(walls.begin(), walls.end());
  std::sort(cpus.begin(), cpus.end());
  out.wall = walls[walls.size() / 2];
  out.cpu = cpus[cpus.size() / 2];
  return out;
}

int Main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      std::fprintf(stderr, "missing value after %s\n", a.c_str());
      return 2;
    }
    const char* v = argv[++i];
    if (a == "--robots")
      o.robots = std::atoi(v);
    else if (a == "--range")
      o.range = std::atof(v);
    else if (a == "--area")
      o.area = std::atof(v);
    else if (a == "--ticks")
      o.ticks = std::atoi(v);
    else if (a == "--threads")
      o.threads = std::atoi(v);
    else if (a == "--occlusions")
      o.occlusions = std::strcmp(v, "true") == 0;
    else if (a == "--repeat")
      o.repeat = std::atoi(v);
    else if (a == "--only")
      o.only = v;
    else if (a == "--cell")
      o.cell = std::atof(v);
    else if (a == "--placement")
      o.grid = std::strcmp(v, "grid") == 0;
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (o.robots <= 0 || o.range <= 0 || o.area <= 0 || o.ticks <= 0 || o.repeat <= 0) {
    std::fprintf(stderr, "robots, range, area, ticks and repeat must be > 0\n");
    return 2;
  }
  if (o.only == "baseline" || o.only == "rab") {
    const Timing t = Measure(o, o.only == "rab");
    std::printf("RESULT %s robots=%d steps_per_s=%.0f cpu_ns_per_robot_step=%.0f\n", o.only.c_str(),
                o.robots, o.robots * o.ticks / t.wall,
                t.cpu / (static_cast<double>(o.robots) * o.ticks) * 1e9);
    return 0;
  }
  const Timing base = Measure(o, false);
  const Timing rab = Measure(o, true);
  const double steps = static_cast<double>(o.robots) * o.ticks;
  std::printf(
      "RESULT robots=%d range=%g area_per_robot=%g occlusions=%s threads=%d ticks=%d "
      "packets_per_robot=%.1f "
      "baseline_steps_per_s=%.0f rab_steps_per_s=%.0f baseline_cpu_ns_per_robot_step=%.0f "
      "rab_cpu_ns_per_robot_step=%.0f rab_extra_cpu_ns_per_robot_step=%.0f\n",
      o.robots, o.range, o.area, o.occlusions ? "true" : "false", o.threads, o.ticks, rab.heard,
      steps / base.wall, steps / rab.wall, base.cpu / steps * 1e9, rab.cpu / steps * 1e9,
      (rab.cpu - base.cpu) / steps * 1e9);
  return 0;
}

}  // namespace
}  // namespace colony

int main(int argc, char** argv) {
  try {
    return colony::Main(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
