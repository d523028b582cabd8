// dynamics3d: 3D rigid-body dynamics on ODE 0.16 (Debian's libode-dev).
//
// One ODE world per engine, with gravity, hash spaces for collisions (movable
// things, each robot's parts in a space of their own, and fixed things) and
// contacts with Coulomb friction (the friction pyramid of dContactApprox1; a
// contact uses the smaller of its two materials' coefficients). The floor is
// static geometry: a plane, or, when the floor has ditches, static boxes
// around the ditch rectangles with the ditch bottoms `depth` lower. Fixed
// entities are static geoms; movable ones are bodies, built by their type's
// model (dynamics3d.h; the marXbot's is entities/marxbot/dynamics3d_model.cpp).
// A cube landing on another within the capture tolerance is put square on it
// and bonded to it with a breakable fixed joint (the magnets beneath it, the
// plates on top). README.md gives the figures and their reasons.
//
// Determinism: everything is added and iterated in slot order (models in the
// order their first entity came); ODE's quickstep draws from one
// process-wide random state, which each engine sets and saves around its
// step under a lock, so engines stepping in parallel do not disturb each
// other's draws.
#include "engines/dynamics3d/dynamics3d.h"

#include <ode/ode.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "core/simulation.h"

namespace colony {
namespace dynamics3d {

// A geom's data holds (owner slot << 8) | (part << 3) | material.
namespace {
void* Tag(uint32_t owner, Material material, uint8_t part = 0) {
  return reinterpret_cast<void*>((static_cast<uintptr_t>(owner) << 8) |
                                 (static_cast<uintptr_t>(part) << 3) | material);
}
uint8_t TagOf(dGeomID g) {
  return static_cast<uint8_t>(reinterpret_cast<uintptr_t>(dGeomGetData(g)) & 0xFF);
}
Material MaterialOf(dGeomID g) { return static_cast<Material>(TagOf(g) & 7); }
}  // namespace

uint32_t Engine::OwnerOf(dGeomID g) {
  return static_cast<uint32_t>(reinterpret_cast<uintptr_t>(dGeomGetData(g)) >> 8);
}
uint8_t Engine::PartOf(dGeomID g) { return TagOf(g) >> 3; }

Space& Engine::entities() { return sim().space(); }

// Entity origin (centre of the base) -> body origin, in the entity's frame.
static Vec3 Up(double z) { return Vec3(0, 0, z); }

dBodyID Engine::MakeBody(uint32_t s, double com_height) { return MakeBody(s, Up(com_height)); }

dBodyID Engine::MakeBody(uint32_t s, const Vec3& com) {
  const Space& space = sim().space();
  const Pose& pose = space.pose(s);
  const Twist& twist = space.twist(s);
  dBodyID b = dBodyCreate(world_);
  const Vec3 arm = pose.orientation * com;
  PlaceBody(b, pose.position + arm, pose.orientation);
  SetBodyVelocity(b, twist.linear + twist.angular.cross(arm), twist.angular);
  slots_[s].body = b;
  slots_[s].com = com;
  return b;
}

dSpaceID Engine::MakePartSpace(uint32_t s) {
  slots_[s].space = dSimpleSpaceCreate(space_);
  return slots_[s].space;
}

dGeomID Engine::AddGeom(uint32_t s, dGeomID g, Material m, uint8_t part) {
  dGeomSetData(g, Tag(s, m, part));
  slots_[s].geoms.push_back(g);
  return g;
}

void Engine::AddSolid(uint32_t s, Material material) {
  const Space& space = sim().space();
  const Geometry& g = space.geometry(s);
  const double mass = space.mass(s) > 0 ? space.mass(s) : 1.0;
  dBodyID b = MakeBody(s, 0.5 * g.height());
  dMass m;
  dGeomID geom;
  if (g.shape == ShapeKind::kBox) {
    dMassSetBoxTotal(&m, mass, g.size.x(), g.size.y(), g.size.z());
    geom = dCreateBox(space_, g.size.x(), g.size.y(), g.size.z());
  } else {
    dMassSetCylinderTotal(&m, mass, 3, g.radius, g.height());
    geom = dCreateCylinder(space_, g.radius, g.height());
  }
  dBodySetMass(b, &m);
  AddGeom(s, geom, material);
  dGeomSetBody(geom, b);
  if (material == kCube) cubes_.insert(std::lower_bound(cubes_.begin(), cubes_.end(), s), s);
}

namespace {

// Calls visit(other, contact) for every geom (fixed or movable, not one of
// `ignore`'s) that probe geom `probe` (in no space) touches.
template <class Visit>
void ProbeSpaces(dSpaceID movable, dSpaceID fixed, dGeomID probe, uint32_t ignore, Visit&& visit) {
  struct Query {
    dGeomID probe;
    uint32_t ignore;
    Visit* visit;
    static void Callback(void* data, dGeomID a, dGeomID b) {
      auto* q = static_cast<Query*>(data);
      if (dGeomIsSpace(a) || dGeomIsSpace(b)) {
        dSpaceCollide2(a, b, data, &Query::Callback);
        return;
      }
      dGeomID other = a == q->probe ? b : a;
      if (q->ignore != kNone && Engine::OwnerOf(other) == q->ignore) return;
      dContactGeom c;
      if (dCollide(q->probe, other, 1, &c, sizeof(dContactGeom)) == 0) return;
      (*q->visit)(other, c);
    }
  };
  Query q{probe, ignore, &visit};
  dSpaceCollide2(probe, reinterpret_cast<dGeomID>(movable), &q, &Query::Callback);
  dSpaceCollide2(probe, reinterpret_cast<dGeomID>(fixed), &q, &Query::Callback);
}

}  // namespace

bool Engine::CastRay(const Vec3& from, const Vec3& direction, double length, uint32_t ignore,
                     RayHit& hit) {
  if (!floor_built_) BuildFloor(sim().space());
  dGeomID ray = dCreateRay(nullptr, length);
  dGeomRaySet(ray, from.x(), from.y(), from.z(), direction.x(), direction.y(), direction.z());
  bool found = false;
  ProbeSpaces(space_, static_, ray, ignore, [&](dGeomID other, const dContactGeom& c) {
    if (found && c.depth >= hit.distance) return;
    found = true;
    hit.distance = c.depth;
    hit.point = ToVec(c.pos);
    hit.material = MaterialOf(other);
    hit.owner = OwnerOf(other);
  });
  dGeomDestroy(ray);
  return found;
}

bool Engine::TouchAt(const Vec3& centre, double radius, uint32_t ignore, Touch& touch) {
  if (!floor_built_) BuildFloor(sim().space());
  dGeomID sphere = dCreateSphere(nullptr, radius);
  dGeomSetPosition(sphere, centre.x(), centre.y(), centre.z());
  bool found = false;
  ProbeSpaces(space_, static_, sphere, ignore, [&](dGeomID other, const dContactGeom&) {
    const uint32_t owner = OwnerOf(other);
    if (found && owner >= touch.owner) return;
    found = true;
    touch.geom = other;
    touch.body = dGeomGetBody(other);
    touch.owner = owner;
    touch.material = MaterialOf(other);
  });
  dGeomDestroy(sphere);
  return found;
}

namespace {

// ODE is initialised once per process; quickstep's random draws come from a
// process-wide state (see the header comment).
std::once_flag ode_init_once;
std::mutex& QuickStepMutex() {
  static std::mutex m;
  return m;
}
void InitOde() {
  std::call_once(ode_init_once, [] { dInitODE2(0); });
  dAllocateODEDataForThread(dAllocateMaskAll);
}

class Dynamics3dEngine : public Engine {
 public:
  Dynamics3dEngine() {
    InitOde();
    world_ = dWorldCreate();
    // Movable things in one space (each robot's parts in a space of their
    // own inside it), fixed ones (floor, walls, fixed objects) in another.
    space_ = dHashSpaceCreate(nullptr);
    dHashSpaceSetLevels(space_, -5, 1);
    static_ = dHashSpaceCreate(nullptr);
    contacts_ = dJointGroupCreate(0);
    dWorldSetAutoDisableFlag(world_, 0);
    // Keep the stepper's working memory between steps rather than freeing
    // and reallocating it.
    dWorldStepReserveInfo reserve{sizeof(dWorldStepReserveInfo), 1.2f, 1u << 20};
    dWorldSetStepMemoryReservationPolicy(world_, &reserve);
  }

  ~Dynamics3dEngine() override {
    dJointGroupDestroy(contacts_);
    dSpaceDestroy(space_);  // destroys the geoms (and robot spaces) it holds
    dSpaceDestroy(static_);
    dWorldDestroy(world_);  // destroys bodies and joints
  }

  void Configure(const ConfigNode& node) override {
    Params& p = params_;
    const auto g = node.GetTriple("gravity", {0, 0, -9.81});
    p.gravity = Vec3(g[0], g[1], g[2]);
    quickstep_ = node.GetChoice("stepper", {"quickstep", "worldstep"}, "quickstep") == "quickstep";
    iterations_ = static_cast<int>(node.GetInt("iterations", 20, 1, 1000));
    substeps_ = static_cast<int>(node.GetInt("substeps", 10, 1, 1000));
    p.erp = node.GetDouble("erp", 0.2, Range::Between(0, 1));
    p.cfm = node.GetDouble("cfm", 1e-5, Range::NonNegative());
    p.friction[kGround] = node.GetDouble("ground_friction", 1.0, Range::NonNegative());
    p.friction[kTread] = node.GetDouble("treel_friction", 0.6, Range::NonNegative());
    p.friction[kBody] = node.GetDouble("body_friction", 0.3, Range::NonNegative());
    p.friction[kCube] = node.GetDouble("cube_friction", 0.5, Range::NonNegative());
    p.friction[kObject] = node.GetDouble("object_friction", 0.5, Range::NonNegative());
    p.friction[kCeiling] = p.friction[kObject];
    p.treel_max_torque = node.GetDouble("treel_max_torque", 0.22, Range::Positive());
    p.magnet_max_force = node.GetDouble("magnet_max_force", 2.0, Range::Positive());
    p.magnet_reach = node.GetDouble("magnet_reach", 0.01, Range::NonNegative());
    p.cube_capture = node.GetDouble("cube_capture", 0.02, Range::NonNegative());
    p.cube_capture_angle = node.GetDouble("cube_capture_angle", 0.35, Range::Between(0, M_PI / 4));
    p.cube_bond_force = node.GetDouble("cube_bond_force", 2.0, Range::Positive());

    p.quickstep = quickstep_;
    p.iterations = iterations_;
    dWorldSetGravity(world_, p.gravity.x(), p.gravity.y(), p.gravity.z());
    dWorldSetERP(world_, p.erp);
    dWorldSetCFM(world_, p.cfm);
    dWorldSetQuickStepNumIterations(world_, iterations_);
    dWorldSetContactSurfaceLayer(world_, 0.0005);
    dWorldSetContactMaxCorrectingVel(world_, 1.0);
  }

  bool Is3D() const override { return true; }

  void AddEntity(EntityHandle entity, PhysicsModel& physics_model) override {
    InitOde();
    auto& model = dynamic_cast<Dynamics3dModel&>(physics_model);
    const Space& space = sim().space();
    const uint32_t s = entity.index;
    if (slots_.size() <= s) slots_.resize(s + 1);
    if (touched_.size() <= s) touched_.resize(s + 1, 0);
    Slot& slot = slots_[s];
    slot = Slot{};
    slot.model = &model;
    if (std::find(models_.begin(), models_.end(), &model) == models_.end())
      models_.push_back(&model);
    if (!space.movable(s)) {
      AddStatic(s, model.fixed_material());
      return;
    }
    model.Add(*this, s);
    movables_.insert(std::lower_bound(movables_.begin(), movables_.end(), s), s);
  }

  void RemoveEntity(EntityHandle entity) override {
    const uint32_t s = entity.index;
    if (s >= slots_.size() || !slots_[s].model) return;
    Slot& slot = slots_[s];
    // Joints first: a body destroyed before its joints would leave them
    // attached to the world.
    for (size_t k = bonds_.size(); k-- > 0;) {
      if (bonds_[k].upper == s || bonds_[k].lower == s) Unbond(k);
    }
    if (slot.held_by != kNone) slots_[slot.held_by].model->Release(*this, slot.held_by, s);
    if (slot.body) slot.model->Remove(*this, s);
    for (dGeomID g : slot.geoms) dGeomDestroy(g);
    if (slot.space) dSpaceDestroy(slot.space);
    if (slot.body) dBodyDestroy(slot.body);
    for (auto* list : {&movables_, &cubes_}) {
      auto it = std::find(list->begin(), list->end(), s);
      if (it != list->end()) list->erase(it);
    }
    slot = Slot{};
  }

  void Step(double dt) override {
    InitOde();
    Space& space = sim().space();
    if (!floor_built_) BuildFloor(space);
    const double h = dt / substeps_;
    for (uint32_t s : movables_) touched_[s] = 0;
    for (Dynamics3dModel* m : models_) m->BeforeStep(*this, dt);
    for (int k = 0; k < substeps_; ++k) {
      for (Dynamics3dModel* m : models_) m->BeforeSubstep(*this, h);
      touches_.clear();
      dSpaceCollide(space_, this, &Dynamics3dEngine::NearCallback);
      dSpaceCollide2(reinterpret_cast<dGeomID>(space_), reinterpret_cast<dGeomID>(static_), this,
                     &Dynamics3dEngine::NearCallback);
      if (params_.cube_capture > 0) CaptureCubes();
      if (quickstep_) {
        std::lock_guard lock(QuickStepMutex());
        dRandSetSeed(random_seed_);
        dWorldQuickStep(world_, h);
        random_seed_ = dRandGetSeed();
      } else {
        dWorldStep(world_, h);
      }
      dJointGroupEmpty(contacts_);
      // Magnets and bonds let go when pulled harder than their limit.
      for (Dynamics3dModel* m : models_) m->AfterSubstep(*this);
      BreakBonds();
    }
    // Whatever fell off the floor's edge stops 1 m below it.
    const double bottom = space.arena_min().z() - 1.0;
    for (uint32_t s : movables_) StopIfFallen(slots_[s], bottom);
    // Stacked cubes touch, though their joint keeps ODE from making contacts.
    for (const Bond& b : bonds_) touched_[b.upper] = touched_[b.lower] = 1;
    for (uint32_t s : movables_) WriteBody(space, s);
    for (Dynamics3dModel* m : models_) m->AfterStep(*this, dt);
  }

 private:
  struct Bond {
    uint32_t upper, lower;
    dJointID joint;
    std::unique_ptr<dJointFeedback> feedback;
  };

  void AddStatic(uint32_t s, Material material) {
    const Space& space = sim().space();
    const Geometry& g = space.geometry(s);
    const Pose& pose = space.pose(s);
    dGeomID geom = g.shape == ShapeKind::kBox
                       ? dCreateBox(static_, g.size.x(), g.size.y(), g.size.z())
                       : dCreateCylinder(static_, g.radius, g.height());
    AddGeom(s, geom, material);
    const Vec3 c = pose.position + pose.orientation * Up(0.5 * g.height());
    dGeomSetPosition(geom, c.x(), c.y(), c.z());
    dQuaternion q;
    SetQuat(q, pose.orientation);
    dGeomSetQuaternion(geom, q);
  }

  // The floor: a plane, or boxes around the ditches with the ditch bottoms
  // `depth` lower. The floor reaches 1 m beyond the arena on every side.
  void BuildFloor(const Space& space) override {
    floor_built_ = true;
    const double z = space.arena_min().z();
    if (space.ceiling()) {
      // The ceiling: a slab 1 m thick above its height, over the floor's extent.
      const Vec3 lo = space.arena_min(), hi = space.arena_max();
      dGeomID slab = dCreateBox(static_, hi.x() - lo.x() + 2, hi.y() - lo.y() + 2, 1.0);
      dGeomSetData(slab, Tag(kNone, kCeiling));
      dGeomSetPosition(slab, 0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()),
                       space.ceiling()->z + 0.5);
    }
    const auto& ditches = space.floor().ditches();
    if (ditches.empty()) {
      dGeomID plane = dCreatePlane(static_, 0, 0, 1, z);
      dGeomSetData(plane, Tag(kNone, kGround));
      return;
    }
    const double x0 = space.arena_min().x() - 1, x1 = space.arena_max().x() + 1;
    const double y0 = space.arena_min().y() - 1, y1 = space.arena_max().y() + 1;
    std::vector<double> xs = {x0, x1}, ys = {y0, y1};
    for (const Ditch& d : ditches) {
      xs.push_back(d.min_x);
      xs.push_back(d.max_x);
      ys.push_back(d.min_y);
      ys.push_back(d.max_y);
    }
    for (auto* v : {&xs, &ys}) {
      std::sort(v->begin(), v->end());
      v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    const size_t nx = xs.size() - 1, ny = ys.size() - 1;
    // Depth of each cell of the grid the ditch edges make (0: floor).
    std::vector<double> depth(nx * ny, 0.0);
    for (size_t j = 0; j < ny; ++j) {
      for (size_t i = 0; i < nx; ++i) {
        const double cx = 0.5 * (xs[i] + xs[i + 1]), cy = 0.5 * (ys[j] + ys[j + 1]);
        for (const Ditch& d : ditches) {
          if (d.Contains(cx, cy)) depth[j * nx + i] = std::max(depth[j * nx + i], d.depth);
        }
      }
    }
    // Greedy rectangles of equal depth: runs along x, grown along y.
    std::vector<uint8_t> used(nx * ny, 0);
    constexpr double kThickness = 1.0;
    for (size_t j = 0; j < ny; ++j) {
      for (size_t i = 0; i < nx; ++i) {
        if (used[j * nx + i]) continue;
        const double dd = depth[j * nx + i];
        size_t i1 = i;
        while (i1 + 1 < nx && !used[j * nx + i1 + 1] && depth[j * nx + i1 + 1] == dd) ++i1;
        size_t j1 = j;
        auto row_matches = [&](size_t jj) {
          for (size_t ii = i; ii <= i1; ++ii)
            if (used[jj * nx + ii] || depth[jj * nx + ii] != dd) return false;
          return true;
        };
        while (j1 + 1 < ny && row_matches(j1 + 1)) ++j1;
        for (size_t jj = j; jj <= j1; ++jj)
          for (size_t ii = i; ii <= i1; ++ii) used[jj * nx + ii] = 1;
        const double lx = xs[i1 + 1] - xs[i], ly = ys[j1 + 1] - ys[j];
        dGeomID box = dCreateBox(static_, lx, ly, kThickness);
        dGeomSetData(box, Tag(kNone, kGround));
        dGeomSetPosition(box, 0.5 * (xs[i] + xs[i1 + 1]), 0.5 * (ys[j] + ys[j1 + 1]),
                         z - dd - 0.5 * kThickness);
      }
    }
  }

  // -------------------------------------------------------------------------
  // Collisions.
  static void NearCallback(void* data, dGeomID a, dGeomID b) {
    static_cast<Dynamics3dEngine*>(data)->Near(a, b);
  }

  void Near(dGeomID a, dGeomID b) {
    if (dGeomIsSpace(a) || dGeomIsSpace(b)) {
      dSpaceCollide2(a, b, this, &Dynamics3dEngine::NearCallback);
      return;
    }
    dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
    if (!ba && !bb) return;
    const uint32_t oa = OwnerOf(a), ob = OwnerOf(b);
    if (oa == ob && oa != kNone) return;  // parts of one entity
    if (ba && bb && dAreConnectedExcluding(ba, bb, dJointTypeContact)) return;
    // A held thing does not collide with what holds it.
    if (oa != kNone && ob != kNone && (slots_[oa].held_by == ob || slots_[ob].held_by == oa))
      return;
    constexpr int kMax = 8;
    dContact contact[kMax];
    const int n = dCollide(a, b, kMax, &contact[0].geom, sizeof(dContact));
    if (n == 0) return;
    const Material ma = MaterialOf(a), mb = MaterialOf(b);
    const double mu = std::min(params_.friction[ma], params_.friction[mb]);
    for (int i = 0; i < n; ++i) {
      dContact& c = contact[i];
      c.surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
      c.surface.mu = mu;
      c.surface.soft_erp = params_.erp;
      c.surface.soft_cfm = params_.cfm;
    }
    // A moving surface touching something other than another moving
    // surface: its model sets the contacts' surface motion.
    dGeomID surface = nullptr;
    if (ma == kTread && mb != kTread) surface = a;
    if (mb == kTread && ma != kTread) surface = b;
    if (surface)
      slots_[OwnerOf(surface)].model->ModifyContacts(*this, surface, surface == a, mu, contact, n);
    for (int i = 0; i < n; ++i) {
      dJointID j = dJointCreateContact(world_, contacts_, &contact[i]);
      dJointAttach(j, ba, bb);
    }
    // Touching anything but the floor counts as a contact.
    if (ma != kGround && mb != kGround) {
      if (oa != kNone) touched_[oa] = 1;
      if (ob != kNone) touched_[ob] = 1;
    }
    if (ma == kCube && mb == kCube && ba && bb)
      touches_.emplace_back(std::min(oa, ob), std::max(oa, ob));
  }

  // -------------------------------------------------------------------------
  // Cubes landing on cubes: a cube that touches down on another's top within
  // the capture tolerance is pulled into alignment by their magnets and
  // plates. ODE cannot carry that pull as a force (the lower cube, as light,
  // would be knocked over by the reaction and the cubes' friction holds the
  // upper one back), so the alignment is instant: the upper cube is put
  // square on the lower one and bonded to it with a breakable fixed joint.
  void CaptureCubes() {
    if (touches_.empty()) return;
    std::sort(touches_.begin(), touches_.end());
    touches_.erase(std::unique(touches_.begin(), touches_.end()), touches_.end());
    const Space& space = sim().space();
    for (const auto& [a, b] : touches_) {
      dBodyID ba = slots_[a].body, bb = slots_[b].body;
      const bool a_low = BodyPos(ba).z() <= BodyPos(bb).z();
      const uint32_t lo = a_low ? a : b, up = a_low ? b : a;
      if (slots_[up].held_by != kNone || Bonded(lo, up)) continue;
      dBodyID bl = slots_[lo].body, bu = slots_[up].body;
      const Quat ql = BodyQuat(bl);
      const Vec3 d = ql.conjugate() * (BodyPos(bu) - BodyPos(bl));  // in the lower cube's frame
      const double rest = 0.5 * (space.geometry(lo).size.z() + space.geometry(up).size.z());
      if (std::abs(d.z() - rest) > 0.01) continue;  // not on its top
      const Quat rel = ql.conjugate() * BodyQuat(bu);
      if ((rel * Vec3::UnitZ()).z() < std::cos(params_.cube_capture_angle)) continue;  // tilted
      if (std::abs(d.x()) > params_.cube_capture || std::abs(d.y()) > params_.cube_capture)
        continue;
      const Vec3 xr = rel * Vec3::UnitX();
      const double quarter = std::round(std::atan2(xr.y(), xr.x()) / (M_PI / 2)) * (M_PI / 2);
      if (std::abs(WrapAngle(std::atan2(xr.y(), xr.x()) - quarter)) > params_.cube_capture_angle)
        continue;
      MakeBond(up, lo, quarter, rest);
    }
  }

  bool Bonded(uint32_t lo, uint32_t up) const {
    for (const Bond& b : bonds_) {
      if (b.lower == lo || b.upper == up || (b.lower == up && b.upper == lo)) return true;
    }
    return false;
  }

  // Puts `up` exactly on top of `lo` (turned by `yaw` about its vertical)
  // and fixes it there.
  void MakeBond(uint32_t up, uint32_t lo, double yaw, double rest) {
    dBodyID bl = slots_[lo].body, bu = slots_[up].body;
    const Quat ql = BodyQuat(bl);
    const Vec3 pl = BodyPos(bl);
    const Vec3 arm = ql * Vec3(0, 0, rest);
    PlaceBody(bu, pl + arm, ql * FromYaw(yaw));
    const Vec3 wl = ToVec(dBodyGetAngularVel(bl));
    SetBodyVelocity(bu, ToVec(dBodyGetLinearVel(bl)) + wl.cross(arm), wl);
    Bond bond{up, lo, dJointCreateFixed(world_, nullptr), std::make_unique<dJointFeedback>()};
    dJointAttach(bond.joint, bu, bl);
    dJointSetFixed(bond.joint);
    dJointSetFeedback(bond.joint, bond.feedback.get());
    bonds_.push_back(std::move(bond));
  }

  void Unbond(size_t k) {
    dJointDestroy(bonds_[k].joint);
    bonds_.erase(bonds_.begin() + static_cast<std::ptrdiff_t>(k));
  }

  void BreakBonds() {
    for (size_t k = bonds_.size(); k-- > 0;) {
      if (ToVec(bonds_[k].feedback->f1).norm() > params_.cube_bond_force) Unbond(k);
    }
  }

  static void StopIfFallen(const Slot& slot, double bottom) {
    if (!dBodyIsEnabled(slot.body) || dBodyGetPosition(slot.body)[2] > bottom) return;
    dBodyDisable(slot.body);
    SetBodyVelocity(slot.body, Vec3::Zero(), Vec3::Zero());
    for (dBodyID part : slot.parts) {
      dBodyDisable(part);
      SetBodyVelocity(part, Vec3::Zero(), Vec3::Zero());
    }
  }

  // -------------------------------------------------------------------------
  // Write-back.
  void WriteBody(Space& space, uint32_t s) {
    const Slot& slot = slots_[s];
    const Quat q = BodyQuat(slot.body);
    const Vec3 origin = BodyPos(slot.body) - q * slot.com;
    Pose& pose = space.pose(s);
    pose.position = origin;
    pose.orientation = q;
    dVector3 v;
    dBodyGetPointVel(slot.body, origin.x(), origin.y(), origin.z(), v);
    Twist& twist = space.twist(s);
    twist.linear = ToVec(v);
    twist.angular = ToVec(dBodyGetAngularVel(slot.body));
    space.set_in_contact(s, touched_[s]);
  }

  dJointGroupID contacts_ = nullptr;
  unsigned long random_seed_ = 0;
  bool quickstep_ = true;
  int iterations_ = 20, substeps_ = 10;

  std::vector<Dynamics3dModel*> models_;                // in the order their first entity came
  std::vector<uint8_t> touched_;                        // per space slot: a contact this tick
  std::vector<std::pair<uint32_t, uint32_t>> touches_;  // cube pairs in contact this sub-step
  std::vector<Bond> bonds_;
};

COLONY_REGISTER_ENGINE(
    Dynamics3dEngine, "dynamics3d",
    "3D rigid-body dynamics (ODE): gravity, floors with ditches, the marXbot on motor-driven "
    "treels, its "
    "construction manipulator and magnet, self-aligning construction cubes",
    (std::vector<AttributeDoc>{
        {"gravity", "\"x,y,z\" (m/s^2)", "0,0,-9.81", "gravity"},
        {"stepper", "quickstep, worldstep", "quickstep",
         "ODE's iterative solver (cost linear in the contacts) or its exact one (per island of "
         "touching "
         "bodies, cost cubic in the island's size)"},
        {"iterations", "a whole number in [1, 1000]", "20", "quickstep iterations per sub-step"},
        {"substeps", "a whole number in [1, 1000]", "10", "physics sub-steps per tick"},
        {"erp", "a number in [0, 1]", "0.2",
         "share of joint and contact error corrected per sub-step"},
        {"cfm", "a number >= 0", "1e-05",
         "constraint force mixing (softness of joints and contacts)"},
        {"ground_friction", "a number >= 0", "1", "friction coefficient of the floor and ditches"},
        {"treel_friction", "a number >= 0", "0.6", "friction coefficient of the treels (rubber)"},
        {"body_friction", "a number >= 0", "0.3",
         "friction coefficient of robot bodies and the manipulator head"},
        {"cube_friction", "a number >= 0", "0.5", "friction coefficient of construction cubes"},
        {"object_friction", "a number >= 0", "0.5",
         "friction coefficient of boxes, cylinders and walls"},
        {"treel_max_torque", "a number > 0 (N m)", "0.22",
         "most torque a treel's motor gives: the treel pushes at most this / wheel radius"},
        {"magnet_max_force", "a number > 0 (N)", "2",
         "force beyond which the magnet lets go of what it holds"},
        {"magnet_reach", "a number >= 0 (m)", "0.01",
         "largest gap between magnet and cube side for a grip"},
        {"cube_capture", "a number >= 0 (m)", "0.02",
         "largest horizontal offset at which a cube landing on another aligns with it (0: never)"},
        {"cube_capture_angle", "a number in [0, 0.785] (rad)", "0.35",
         "largest turn from the cube below at which a landing cube aligns with it"},
        {"cube_bond_force", "a number > 0 (N)", "2",
         "force beyond which two stacked cubes come apart"},
    }));

}  // namespace
}  // namespace dynamics3d
}  // namespace colony
