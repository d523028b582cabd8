// pocket_metrics: the barrier-construction experiment of seed 004 (3.1, 4.2,
// 5.2-5.3): refills the reservoirs with pockets and measures the structure
// the robots build, from ground truth. README.md documents the parameters,
// the metrics and the choices made where the seed is silent.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/entity_type.h"
#include "core/experiment_spec.h"
#include "core/loop_functions.h"
#include "core/run_files.h"
#include "core/simulation.h"
#include "entities/objects/pocket.h"
#include "loop_functions/pocket_metrics/metrics.h"

namespace colony {
namespace {

// `text` split at `separator`, each piece trimmed of spaces; empty pieces
// dropped.
std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> pieces;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find(separator, start);
    if (end == std::string::npos) end = text.size();
    const size_t first = text.find_first_not_of(" \t\n", start);
    if (first != std::string::npos && first < end) {
      const size_t last = text.find_last_not_of(" \t\n", end - 1);
      pieces.push_back(text.substr(first, last - first + 1));
    }
    start = end + 1;
  }
  return pieces;
}

Vec2 Xy(const Vec3& p) { return p.head<2>(); }

class PocketMetrics : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    Space& space = sim().space();
    for (uint32_t s = 0; s < space.slots(); ++s) {
      if (!space.alive(s)) continue;
      if (space.TypeLabel(space.type(s)) == "pocket") pockets_.push_back(space.HandleOf(s));
      if (!(space.flags(s) & kRobot)) continue;
      if (robots_.empty()) robot_radius_ = space.geometry(s).radius;
      robots_.push_back(space.HandleOf(s));
    }
    ReadTemplate(params);
    ReadReservoirs(params);
    ReadQuota(params);
    structure_width_ = params.GetDouble("structure_width", 0.3, 0.001);
    bandwidth_ = params.GetDouble("bandwidth", pockets::DefaultBandwidth(), 1e-6);
    robot_radius_ = params.GetDouble("robot_radius", robot_radius_, 0);
    const Vec3 extent = space.arena_max() - space.arena_min();
    const double area = params.GetDouble("arena_area", extent.x() * extent.y(), 1e-6);
    if (params.Has("reference_iteration_time")) {
      reference_ = params.GetDouble("reference_iteration_time", 0, 1e-9);
    }
    ReadCsv(params);
    stop_ = params.GetBool("stop", true);
    const double threshold = params.GetDouble("occlusion_threshold", 75, 0, 100);
    if (!reservoirs_.empty()) {
      // Read one pocket; every pocket supplied is a copy of it.
      new_pocket_ = ReadEntityDesc("<pocket id=\"pocket\"><body position=\"0,0,0\"/></pocket>",
                                   "pocket_metrics");
      new_pocket_.init.components.Add(PocketState{}).threshold = threshold / 100;
    }
    CheckReservoirsOutsideStructure();
    density_ = pockets::SwarmDensity(robot_radius_, robots_.size(), area);
    for (Reservoir& r : reservoirs_) {
      if (supplied_ >= quota_) break;
      r.pocket = PocketAt(r.location);
      if (!r.pocket.valid()) r.pocket = AddPocket(r);
      ++supplied_;
    }
    Publish(CountDeposited());
  }

  void PostStep() override {
    Refill();
    const int deposited = CountDeposited();
    if (!finished_ && deposited >= quota_) Finish(deposited);
    const bool last = sim().length_ticks() > 0 && sim().tick() >= sim().length_ticks();
    if (!csv_.empty() && !csv_written_ && (finished_ || last)) WriteCsv();
    Publish(deposited);
  }

  bool IsExperimentFinished() override { return stop_ && finished_; }

 private:
  // A place where pockets are supplied: on the floor midway between two
  // landmarks, the pocket's long axis along the line joining them.
  struct Reservoir {
    Vec2 location;
    double yaw = 0;
    EntityHandle pocket;  // the pocket supplied there last
    bool picked = false;  // that pocket has been held since
  };

  void Publish(int deposited) {
    Metrics& m = sim().metrics();
    m.Set("deposited", deposited);
    m.Set("supplied", supplied_);
    m.Set("uniformity_deviation", uniformity_);
    m.Set("integrity_deviation", integrity_);
    m.Set("maximum_gap", gap_);
    m.Set("construction_time", construction_time_);
    m.Set("average_iteration_time", iteration_time_);
    m.Set("ideal_iteration_time", ideal_time_);
    m.Set("swarm_density", density_);
    m.Set("efficiency", efficiency_);
  }

  // Where landmark `id`, named by parameter `key`, stands.
  Vec2 Landmark(const std::string& key, const std::string& id) const {
    const Space& space = sim().space();
    const EntityHandle h = space.Find(id);
    const std::string prefix = "parameter '" + key + "': ";
    if (!h.valid()) throw ParamError(key, id, prefix + "no entity '" + id + "' in the arena");
    if (space.TypeLabel(space.type(h.index)) != "landmark") {
      throw ParamError(key, id,
                       prefix + "'" + id + "' is a " + space.TypeLabel(space.type(h.index)) +
                           ", not a landmark");
    }
    return Xy(space.pose(h.index).position);
  }

  void ReadTemplate(const Params& params) {
    const Space& space = sim().space();
    std::vector<Vec2> points;
    std::string key = "template";
    if (params.Has("template")) {
      for (const std::string& id : Split(params.GetString("template"), ',')) {
        points.push_back(Landmark(key, id));
      }
    } else {
      key = "template_prefix";
      const std::string prefix = params.GetString(key, "template");
      for (uint32_t s = 0; s < space.slots(); ++s) {
        if (space.alive(s) && space.TypeLabel(space.type(s)) == "landmark" &&
            space.id(s).starts_with(prefix)) {
          points.push_back(Xy(space.pose(s).position));
        }
      }
    }
    const auto frame = pockets::FrameThrough(points);
    if (!frame) {
      throw ParamError(key, params.GetString(key, "template"),
                       "parameter '" + key + "': the template needs two landmarks or more, " +
                           "not all at one place, to form a boundary (found " +
                           std::to_string(points.size()) + ")");
    }
    // Seed 004's boundary is straight (3.1): every template landmark lies on
    // the line (within the landmark's own size).
    for (size_t i = 0; i < points.size(); ++i) {
      const double off = std::abs(frame->ToFrame(points[i]).y());
      if (off > kStraightTolerance) {
        throw ParamError(key, params.GetString(key, "template"),
                         "parameter '" + key +
                             "': the template landmarks do not form a straight "
                             "boundary: landmark " +
                             std::to_string(i + 1) + " of " + std::to_string(points.size()) +
                             " lies " + std::to_string(off) +
                             " m off the line through them (at most " +
                             std::to_string(kStraightTolerance) + " m)");
      }
    }
    frame_ = *frame;
  }

  // How far (m) a template landmark may lie off the boundary's line.
  static constexpr double kStraightTolerance = 0.05;

  void ReadReservoirs(const Params& params) {
    const std::string text = params.GetString("reservoirs", "");
    for (const std::string& pair : Split(text, ';')) {
      const std::vector<std::string> ids = Split(pair, ',');
      if (ids.size() != 2) {
        throw ParamError("reservoirs", pair,
                         "parameter 'reservoirs': '" + pair +
                             "' is not a pair of landmark ids; accepted: \"a,b; c,d; ...\"");
      }
      const Vec2 a = Landmark("reservoirs", ids[0]), b = Landmark("reservoirs", ids[1]);
      if ((b - a).norm() < pocket::kLength) {
        throw ParamError("reservoirs", pair,
                         "parameter 'reservoirs': landmarks '" + ids[0] + "' and '" + ids[1] +
                             "' are closer than a pocket's length (0.12 m); a pocket lies "
                             "between them");
      }
      reservoirs_.push_back({0.5 * (a + b), std::atan2(b.y() - a.y(), b.x() - a.x()), {}, false});
    }
  }

  void ReadQuota(const Params& params) {
    if (params.Has("quota") && reservoirs_.empty()) {
      throw ParamError("quota", params.GetString("quota"),
                       "parameter 'quota': no reservoirs to supply the pockets; give "
                       "reservoirs=\"a,b; ...\" (pairs of landmark ids)");
    }
    if (!reservoirs_.empty() && !params.Has("quota")) {
      throw ParamError("quota", "",
                       "parameter 'quota': how many pockets the reservoirs supply, a whole "
                       "number >= 1, is required with reservoirs");
    }
    if (reservoirs_.empty() && pockets_.empty()) {
      throw ParamError("reservoirs", "",
                       "parameter 'reservoirs': the arena has no pockets and no reservoirs to "
                       "supply them");
    }
    quota_ =
        static_cast<int>(params.GetInt("quota", static_cast<int64_t>(pockets_.size()), 1, 1000000));
  }

  // A reservoir's pocket must not count as deposited.
  void CheckReservoirsOutsideStructure() const {
    for (const Reservoir& r : reservoirs_) {
      if (frame_.DistanceToSegment(r.location) > structure_width_) continue;
      char where[64];
      std::snprintf(where, sizeof where, "%g,%g", r.location.x(), r.location.y());
      throw ParamError("structure_width", std::to_string(structure_width_),
                       "parameter 'structure_width': the reservoir at (" + std::string(where) +
                           ") lies within it of the boundary; its pocket would count as "
                           "deposited");
    }
  }

  // The CSV's path: `csv` if given (its folder must exist), else pockets.csv
  // in the run folder (made by the program after loading), else none.
  void ReadCsv(const Params& params) {
    csv_ = params.GetString("csv", "");
    if (csv_.empty()) {
      if (!sim().run_folder().empty())
        csv_ = (std::filesystem::path(sim().run_folder()) / "pockets.csv").string();
      return;
    }
    const std::filesystem::path folder = std::filesystem::absolute(csv_).parent_path();
    if (!std::filesystem::is_directory(folder)) {
      throw ParamError("csv", csv_,
                       "parameter 'csv': no folder '" + folder.string() + "' to write it in");
    }
  }

  // A pocket not held whose centre is within half a pocket width of `p`.
  EntityHandle PocketAt(const Vec2& p) const {
    const Space& space = sim().space();
    for (const EntityHandle& h : pockets_) {
      if (!space.IsAlive(h) || Held(h)) continue;
      if ((Xy(space.pose(h.index).position) - p).norm() < 0.5 * pocket::kWidth) return h;
    }
    return {};
  }

  bool Held(const EntityHandle& h) const {
    const PocketState* state = sim().space().Get<PocketState>(h.index);
    return state && state->holder != PocketState::kNobody;
  }

  EntityHandle AddPocket(const Reservoir& r) {
    Space& space = sim().space();
    EntityDesc desc = new_pocket_;
    do {
      desc.init.id = "supplied_pocket_" + std::to_string(next_id_++);
    } while (space.Find(desc.init.id).valid());
    desc.init.pose.position = Vec3(r.location.x(), r.location.y(), space.arena_min().z());
    desc.init.pose.orientation = FromYaw(r.yaw);
    const EntityHandle h = sim().AddEntity(desc);
    SettlePocket(space, h.index);
    pockets_.push_back(h);
    return h;
  }

  // A new pocket appears at a reservoir once the one there has been picked
  // up and carried clear of the place, and no robot stands on it, until the
  // quota has been supplied.
  void Refill() {
    const Space& space = sim().space();
    const double reach = 0.5 * std::hypot(pocket::kLength, pocket::kWidth);
    for (Reservoir& r : reservoirs_) {
      if (supplied_ >= quota_) return;
      const bool there = space.IsAlive(r.pocket);
      r.picked = r.picked || !there || Held(r.pocket);
      if (!r.picked) continue;
      if (there && (Xy(space.pose(r.pocket.index).position) - r.location).norm() < 2 * reach) {
        continue;
      }
      const bool robot_on_it = std::any_of(robots_.begin(), robots_.end(), [&](EntityHandle h) {
        return space.IsAlive(h) && (Xy(space.pose(h.index).position) - r.location).norm() <
                                       space.geometry(h.index).radius + reach;
      });
      if (robot_on_it) continue;
      r.pocket = AddPocket(r);
      r.picked = false;
      ++supplied_;
    }
  }

  bool Deposited(const EntityHandle& h) const {
    const Space& space = sim().space();
    return space.IsAlive(h) && !Held(h) &&
           frame_.DistanceToSegment(Xy(space.pose(h.index).position)) <= structure_width_;
  }

  int CountDeposited() const {
    return static_cast<int>(std::count_if(pockets_.begin(), pockets_.end(),
                                          [&](EntityHandle h) { return Deposited(h); }));
  }

  // The criteria of the final structure (4.2) and the iteration figures (5.2-5.3).
  void Finish(int deposited) {
    const Space& space = sim().space();
    std::vector<double> along, across;
    for (const EntityHandle& h : pockets_) {
      if (!Deposited(h)) continue;
      const Vec2 f = frame_.ToFrame(Xy(space.pose(h.index).position));
      along.push_back(f.x());
      across.push_back(f.y());
    }
    finished_ = true;
    uniformity_ = pockets::UniformityDeviation(along, 0, frame_.length, bandwidth_);
    integrity_ = pockets::IntegrityDeviation(across);
    gap_ = pockets::MaximumGap(along);
    construction_time_ = sim().time();
    iteration_time_ = pockets::AverageIterationTime(construction_time_, deposited);
    const size_t m = robots_.size();
    double reference = reference_;
    if (reference <= 0 && m == 1) reference = iteration_time_;
    if (reference > 0 && m > 0) {
      ideal_time_ = pockets::IdealIterationTime(reference, m);
      efficiency_ = pockets::Efficiency(iteration_time_, reference, m);
    }
  }

  // Every pocket: id, x, y (m, world), z (m above the floor, its bottom),
  // along, across (m, the structure's frame), occlusion (0..1), held and
  // deposited (0/1).
  void WriteCsv() {
    const Space& space = sim().space();
    std::string text = "id,x,y,z,along,across,occlusion,held,deposited\n";
    char row[256];
    for (const EntityHandle& h : pockets_) {
      if (!space.IsAlive(h)) continue;
      const Vec3& p = space.pose(h.index).position;
      const Vec2 f = frame_.ToFrame(Xy(p));
      const PocketState* state = space.Get<PocketState>(h.index);
      std::snprintf(row, sizeof row, ",%.6f,%.6f,%.6f,%.6f,%.6f,%.4f,%d,%d\n", p.x(), p.y(),
                    p.z() - space.arena_min().z(), f.x(), f.y(), state ? state->occlusion : 0.0,
                    Held(h) ? 1 : 0, Deposited(h) ? 1 : 0);
      text += space.id(h.index);
      text += row;
    }
    WriteFileAtomically(csv_, text);
    csv_written_ = true;
  }

  pockets::StructureFrame frame_;
  std::vector<Reservoir> reservoirs_;
  std::vector<EntityHandle> pockets_, robots_;
  EntityDesc new_pocket_;
  std::string csv_;
  int quota_ = 0, supplied_ = 0, next_id_ = 0;
  double structure_width_ = 0.3, bandwidth_ = 0, robot_radius_ = 0, reference_ = 0;
  double density_ = 0;
  bool stop_ = true, finished_ = false, csv_written_ = false;
  double uniformity_ = -1, integrity_ = -1, gap_ = -1, construction_time_ = -1;
  double iteration_time_ = -1, ideal_time_ = -1, efficiency_ = -1;
};

COLONY_REGISTER_LOOP_FUNCTIONS(
    PocketMetrics, "pocket_metrics",
    "reservoir refill and the structure criteria of seed 004 (u_d, i_d, d_m, t_c; 4.2) and its "
    "swarm figures (5.1-5.4), from ground truth",
    {{"template", "landmark ids, comma-separated (2 or more)", "those of template_prefix",
      "the landmarks of the boundary: its line and its length"},
     {"template_prefix", "a text", "template",
      "without template: every landmark whose id starts with it"},
     {"reservoirs", "pairs of landmark ids: \"a,b; c,d\"", "none",
      "a pocket is supplied midway between each pair, along the line joining them"},
     {"quota", "a whole number >= 1", "required with reservoirs; else the pockets present",
      "pockets supplied in all; the run is complete when as many are deposited"},
     {"structure_width", "a number > 0 (m)", "0.3",
      "a pocket not held within this distance of the boundary segment is deposited"},
     {"bandwidth", "a number > 0 (m)", "0.0346 (12 cm / sqrt 12)",
      "kernel bandwidth h of u_d along the length"},
     {"robot_radius", "a number >= 0 (m)", "the first robot's radius", "R of the swarm density"},
     {"arena_area", "a number > 0 (m^2)", "the arena's floor area", "A_a of the swarm density"},
     {"reference_iteration_time", "a number > 0 (s)", "this run's own with one robot, else none",
      "xi_c(1), for the ideal iteration time and the efficiency"},
     {"occlusion_threshold", "a number in [0, 100] (%)", "75",
      "occlusion threshold of the pockets it supplies"},
     {"csv", "a file path", "none (no file)",
      "where to write every pocket's final position, height and occlusion"},
     {"stop", "true, false", "true", "end the run once the quota is deposited"}});

}  // namespace
}  // namespace colony
