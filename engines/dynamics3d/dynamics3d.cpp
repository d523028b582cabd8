// dynamics3d: 3D rigid-body dynamics on ODE 0.16 (Debian's libode-dev).
//
// One ODE world per engine, with gravity, hash spaces for collisions (movable
// things, each robot's parts in a space of their own, and fixed things) and
// contacts with Coulomb friction (the friction pyramid of dContactApprox1; a
// contact uses the smaller of its two materials' coefficients). The floor is
// static geometry: a plane, or, when the floor has ditches, static boxes
// around the ditch rectangles with the ditch bottoms `depth` lower. Fixed
// entities are static geoms; movable ones are bodies.
//
// The marXbot is one rigid body: the round body, a low central belly (the
// battery) and two treels of two wheels each. A treel's tread moves at the
// treel's commanded speed (ODE's contact surface motion along the wheel's
// rolling direction), so the ground pushes the robot as a turning wheel
// would, up to min(friction x load, motor torque / wheel radius); beyond that
// the tread slips. With manipulator="true" a head rides on a piston joint in
// front of the body (slides up and down, turns about its vertical axis),
// both motions motor-driven at the state's speeds; its magnet, when fully
// engaged, holds the construction cube whose low side plate it touches with
// a breakable fixed joint. A cube landing on another within the capture
// tolerance is put square on it and bonded to it with a breakable fixed
// joint (the magnets beneath it, the plates on top). README.md gives the
// figures and their reasons.
//
// Determinism: everything is added and iterated in slot order; ODE's
// quickstep draws from one process-wide random state, which each engine sets
// and saves around its step under a lock, so engines stepping in parallel do
// not disturb each other's draws.
#include <ode/ode.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "actuators/manipulator/manipulator_state.h"
#include "core/engine.h"
#include "core/simulation.h"
#include "entities/marxbot/marxbot.h"

namespace colony {
namespace {

constexpr uint32_t kNone = 0xFFFFFFFFu;

// ---------------------------------------------------------------------------
// The marXbot in 3D (robot frame: x forward, y left, z up, origin at the
// centre of the base on the floor). Figures not in the sources are choices,
// explained in README.md (they were tuned so that the robot falls into a
// ditch one cube wide and deep, and crosses it over two cubes).
struct MarxbotGeometry {
  double treel_wheel_radius = 0.025;  // m, the spheres the treels touch the ground with
  double treel_y = 0.06;              // m, treel contact lines at y = +-0.06
  double treel_half_span = 0.03;      // m, wheels at x = +-0.03
  double belly_half_length = 0.03;    // m, the central belly (battery) box: 6 cm long,
  double belly_half_width = 0.04;     // 8 cm wide,
  double belly_bottom = 0.006;        // 6 mm above the floor,
  double belly_top = 0.04;            // up to 4 cm
  double body_bottom = 0.05;          // m, bottom of the round body
  double com_height = 0.05;           // m, centre of mass (battery low in the base)
  double com_height_manipulator = 0.07;
};
constexpr MarxbotGeometry kMarxbot3d;
// The construction manipulator's head: a box in front of the body whose outer
// face (local +x) is the magnet. It turns about its own vertical axis.
constexpr double kHeadDepth = 0.03, kHeadWidth = 0.05, kHeadHeight = 0.03;  // m
constexpr double kHeadPivotX = marxbot::kBodyRadius + 0.5 * kHeadDepth;     // m from the robot's axis
constexpr double kHeadMass = 0.15;                                         // kg
constexpr double kHeadMaxForce = 50.0;    // N, elevation motor
constexpr double kHeadMaxTorque = 2.0;    // N m, rotation motor
// The magnet holds a cube's side where its ferromagnetic plate is: the lower
// half of the side (the magnet face is kHeadHeight tall).
constexpr double kMagnetAlignment = 0.866;
// Sideways yield of a treel's tread: sliding speed per newton (m/s / N).
constexpr double kTreelSideSlip = 0.005;

// ---------------------------------------------------------------------------
// Materials and geom tags. A geom's data holds (owner slot << 8) | material.
// The treels are one material with two tags, so a contact knows its side.
enum Material : uint8_t { kGround, kTreel, kBody, kCube, kObject, kMaterials };
enum TreelTag : uint8_t { kLeftTreel = kTreel, kRightTreel = kMaterials };

void* Tag(uint32_t owner, uint8_t tag) {
  return reinterpret_cast<void*>((static_cast<uintptr_t>(owner) << 8) | tag);
}
uint32_t OwnerOf(dGeomID g) { return static_cast<uint32_t>(reinterpret_cast<uintptr_t>(dGeomGetData(g)) >> 8); }
uint8_t TagOf(dGeomID g) { return static_cast<uint8_t>(reinterpret_cast<uintptr_t>(dGeomGetData(g)) & 0xFF); }
Material MaterialOf(dGeomID g) {
  const uint8_t t = TagOf(g);
  return t >= kMaterials ? kTreel : static_cast<Material>(t);
}

// ---------------------------------------------------------------------------
// Conversions.
Vec3 ToVec(const dReal* v) { return Vec3(v[0], v[1], v[2]); }
Quat ToQuat(const dReal* q) { return Quat(q[0], q[1], q[2], q[3]).normalized(); }
void SetQuat(dQuaternion out, const Quat& q) {
  out[0] = q.w();
  out[1] = q.x();
  out[2] = q.y();
  out[3] = q.z();
}
Quat BodyQuat(dBodyID b) { return ToQuat(dBodyGetQuaternion(b)); }
Vec3 BodyPos(dBodyID b) { return ToVec(dBodyGetPosition(b)); }
void PlaceBody(dBodyID b, const Vec3& p, const Quat& q) {
  dBodySetPosition(b, p.x(), p.y(), p.z());
  dQuaternion dq;
  SetQuat(dq, q);
  dBodySetQuaternion(b, dq);
}
void SetBodyVelocity(dBodyID b, const Vec3& v, const Vec3& w) {
  dBodySetLinearVel(b, v.x(), v.y(), v.z());
  dBodySetAngularVel(b, w.x(), w.y(), w.z());
}

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

// ---------------------------------------------------------------------------
// Models.
enum class Kind : uint8_t { kNone, kMarxbot, kBox, kCylinder, kCube };

class Dynamics3dModel : public PhysicsModel {
 public:
  explicit Dynamics3dModel(Kind kind) : kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

struct MarxbotModel : Dynamics3dModel {
  MarxbotModel() : Dynamics3dModel(Kind::kMarxbot) {}
};
struct BoxModel : Dynamics3dModel {
  BoxModel() : Dynamics3dModel(Kind::kBox) {}
};
struct CylinderModel : Dynamics3dModel {
  CylinderModel() : Dynamics3dModel(Kind::kCylinder) {}
};
struct CubeModel : Dynamics3dModel {
  CubeModel() : Dynamics3dModel(Kind::kCube) {}
};

COLONY_REGISTER_PHYSICS_MODEL(MarxbotModel, "dynamics3d:marxbot",
                              "one body on two treels of two wheels each, whose treads move at the wheel speeds "
                              "(torque-limited, slip); with manipulator=\"true\" a motor-driven head carrying a "
                              "magnet",
                              (std::vector<std::string>{"drive", "manipulator"}));
COLONY_REGISTER_PHYSICS_MODEL(BoxModel, "dynamics3d:box", "box: a body of its mass if movable, static geometry otherwise",
                              (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(CylinderModel, "dynamics3d:cylinder",
                              "upright cylinder: a body of its mass if movable, static geometry otherwise",
                              (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(CubeModel, "dynamics3d:cube",
                              "construction cube: held by the manipulator's magnet; self-aligns and bonds when "
                              "it lands on another cube within the capture tolerance",
                              (std::vector<std::string>{}));

// ---------------------------------------------------------------------------
class Dynamics3dEngine : public PhysicsEngine {
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
    const auto g = node.GetTriple("gravity", {0, 0, -9.81});
    gravity_ = Vec3(g[0], g[1], g[2]);
    quickstep_ = node.GetChoice("stepper", {"quickstep", "worldstep"}, "quickstep") == "quickstep";
    iterations_ = static_cast<int>(node.GetInt("iterations", 20, 1, 1000));
    substeps_ = static_cast<int>(node.GetInt("substeps", 10, 1, 1000));
    erp_ = node.GetDouble("erp", 0.2, Range::Between(0, 1));
    cfm_ = node.GetDouble("cfm", 1e-5, Range::NonNegative());
    friction_[kGround] = node.GetDouble("ground_friction", 1.0, Range::NonNegative());
    friction_[kTreel] = node.GetDouble("treel_friction", 0.6, Range::NonNegative());
    friction_[kBody] = node.GetDouble("body_friction", 0.3, Range::NonNegative());
    friction_[kCube] = node.GetDouble("cube_friction", 0.5, Range::NonNegative());
    friction_[kObject] = node.GetDouble("object_friction", 0.5, Range::NonNegative());
    treel_max_torque_ = node.GetDouble("treel_max_torque", 0.22, Range::Positive());
    magnet_max_force_ = node.GetDouble("magnet_max_force", 2.0, Range::Positive());
    magnet_reach_ = node.GetDouble("magnet_reach", 0.01, Range::NonNegative());
    cube_capture_ = node.GetDouble("cube_capture", 0.02, Range::NonNegative());
    cube_capture_angle_ = node.GetDouble("cube_capture_angle", 0.35, Range::Between(0, M_PI / 4));
    cube_bond_force_ = node.GetDouble("cube_bond_force", 2.0, Range::Positive());

    dWorldSetGravity(world_, gravity_.x(), gravity_.y(), gravity_.z());
    dWorldSetERP(world_, erp_);
    dWorldSetCFM(world_, cfm_);
    dWorldSetQuickStepNumIterations(world_, iterations_);
    dWorldSetContactSurfaceLayer(world_, 0.0005);
    dWorldSetContactMaxCorrectingVel(world_, 1.0);
  }

  bool Is3D() const override { return true; }

  void AddEntity(EntityHandle entity, PhysicsModel& model) override {
    InitOde();
    const Kind kind = dynamic_cast<const Dynamics3dModel&>(model).kind();
    const Space& space = sim().space();
    const uint32_t s = entity.index;
    if (slots_.size() <= s) slots_.resize(s + 1);
    if (touched_.size() <= s) touched_.resize(s + 1, 0);
    Slot& slot = slots_[s];
    slot = Slot{};
    slot.kind = kind;
    if (!space.movable(s)) {
      AddStatic(s, kind);
      return;
    }
    if (kind == Kind::kMarxbot && space.drive(s)) {
      AddRobot(s);
    } else {
      AddObject(s, kind);
    }
  }

  void RemoveEntity(EntityHandle entity) override {
    const uint32_t s = entity.index;
    if (s >= slots_.size() || slots_[s].kind == Kind::kNone) return;
    Slot& slot = slots_[s];
    // Joints first: a body destroyed before its joints would leave them
    // attached to the world.
    for (size_t k = bonds_.size(); k-- > 0;) {
      if (bonds_[k].upper == s || bonds_[k].lower == s) Unbond(k);
    }
    if (slot.held_by != kNone) Release(*RobotAt(slot.held_by));
    if (slot.robot) {
      Robot& r = *slot.robot;
      if (r.magnet_joint) Release(r);
      if (r.head) {
        dJointDestroy(r.piston);
        dBodyDestroy(r.head);
      }
      robots_.erase(std::find(robots_.begin(), robots_.end(), slot.robot.get()));
    }
    for (dGeomID g : slot.geoms) dGeomDestroy(g);
    if (slot.space) dSpaceDestroy(slot.space);
    if (slot.body) dBodyDestroy(slot.body);
    for (auto* list : {&objects_, &cubes_}) {
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
    for (Robot* r : robots_) {
      touched_[r->slot] = 0;
      SetTreads(space, *r);
      if (r->head) UpdateMagnet(space, *r, dt);
    }
    for (uint32_t s : objects_) touched_[s] = 0;
    for (int k = 0; k < substeps_; ++k) {
      for (Robot* r : robots_) {
        if (r->head) DriveHead(space, *r, h);
      }
      touches_.clear();
      dSpaceCollide(space_, this, &Dynamics3dEngine::NearCallback);
      dSpaceCollide2(reinterpret_cast<dGeomID>(space_), reinterpret_cast<dGeomID>(static_), this,
                     &Dynamics3dEngine::NearCallback);
      if (cube_capture_ > 0) CaptureCubes();
      if (quickstep_) {
        std::lock_guard lock(QuickStepMutex());
        dRandSetSeed(random_seed_);
        dWorldQuickStep(world_, h);
        random_seed_ = dRandGetSeed();
      } else {
        dWorldStep(world_, h);
      }
      dJointGroupEmpty(contacts_);
      CheckBreaks();
    }
    // Whatever fell off the floor's edge stops 1 m below it.
    const double bottom = space.arena_min().z() - 1.0;
    for (Robot* r : robots_) StopIfFallen(slots_[r->slot].body, r->head, bottom);
    for (uint32_t s : objects_) StopIfFallen(slots_[s].body, nullptr, bottom);
    // Stacked cubes touch, though their joint keeps ODE from making contacts.
    for (const Bond& b : bonds_) touched_[b.upper] = touched_[b.lower] = 1;
    for (Robot* r : robots_) WriteRobot(space, *r, dt);
    for (uint32_t s : objects_) WriteBody(space, s);
  }

 private:
  struct Robot {
    uint32_t slot = kNone;
    double wheel_base = 0.14;
    double tread[2] = {0, 0};  // left, right treel tread speed this tick (m/s)
    double pull_limit = 1;     // treel_max_torque / wheel radius / (half the robot's weight)
    // Manipulator (head == nullptr: none).
    dBodyID head = nullptr;
    dJointID piston = nullptr;
    double elevation0 = 0, rotation0 = 0;  // joint positions when the joints were made
    dJointID magnet_joint = nullptr;
    dJointFeedback magnet_feedback{};
    uint32_t held = kNone;
  };
  struct Slot {
    Kind kind = Kind::kNone;
    dBodyID body = nullptr;
    dSpaceID space = nullptr;  // robots: the space of their parts
    std::vector<dGeomID> geoms;
    double com_height = 0;     // body origin above the entity's origin, in its frame (m)
    std::unique_ptr<Robot> robot;  // also listed in robots_
    uint32_t held_by = kNone;  // cubes: the robot whose magnet holds it
  };
  struct Bond {
    uint32_t upper, lower;
    dJointID joint;
    std::unique_ptr<dJointFeedback> feedback;
  };

  Robot* RobotAt(uint32_t s) { return slots_[s].robot.get(); }

  dGeomID AddGeom(Slot& slot, dGeomID g, uint32_t owner, uint8_t tag) {
    dGeomSetData(g, Tag(owner, tag));
    slot.geoms.push_back(g);
    return g;
  }

  // Entity origin (centre of the base) -> body origin, in the entity's frame.
  static Vec3 Up(double z) { return Vec3(0, 0, z); }

  void AddStatic(uint32_t s, Kind kind) {
    const Space& space = sim().space();
    Slot& slot = slots_[s];
    const Geometry& g = space.geometry(s);
    const Pose& pose = space.pose(s);
    dGeomID geom = g.shape == ShapeKind::kBox ? dCreateBox(static_, g.size.x(), g.size.y(), g.size.z())
                                              : dCreateCylinder(static_, g.radius, g.height());
    AddGeom(slot, geom, s, kind == Kind::kCube ? kCube : kObject);
    const Vec3 c = pose.position + pose.orientation * Up(0.5 * g.height());
    dGeomSetPosition(geom, c.x(), c.y(), c.z());
    dQuaternion q;
    SetQuat(q, pose.orientation);
    dGeomSetQuaternion(geom, q);
  }

  // Creates a body at the entity's pose and velocity, its origin com_height
  // above the entity's origin.
  dBodyID MakeBody(uint32_t s, double com_height) {
    const Space& space = sim().space();
    const Pose& pose = space.pose(s);
    const Twist& twist = space.twist(s);
    dBodyID b = dBodyCreate(world_);
    const Vec3 arm = pose.orientation * Up(com_height);
    PlaceBody(b, pose.position + arm, pose.orientation);
    SetBodyVelocity(b, twist.linear + twist.angular.cross(arm), twist.angular);
    slots_[s].body = b;
    slots_[s].com_height = com_height;
    return b;
  }

  void AddObject(uint32_t s, Kind kind) {
    const Space& space = sim().space();
    Slot& slot = slots_[s];
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
    AddGeom(slot, geom, s, kind == Kind::kCube ? kCube : kObject);
    dGeomSetBody(geom, b);
    InsertSorted(objects_, s);
    if (kind == Kind::kCube) InsertSorted(cubes_, s);
  }

  void AddRobot(uint32_t s) {
    using namespace marxbot;
    const MarxbotGeometry& geo = kMarxbot3d;
    Space& space = sim().space();
    Slot& slot = slots_[s];
    const Geometry& g = space.geometry(s);
    const DriveState& drive = *space.drive(s);
    const ManipulatorState* manip = space.Get<ManipulatorState>(s);
    const Pose& pose = space.pose(s);
    const Twist& twist = space.twist(s);
    const double total = space.mass(s) > 0 ? space.mass(s) : kMass;
    const double com = manip ? geo.com_height_manipulator : geo.com_height;
    const double height = g.height();
    const double radius = g.radius;

    slot.robot = std::make_unique<Robot>();
    Robot* r = slot.robot.get();
    r->slot = s;
    r->wheel_base = drive.wheel_base > 0 ? drive.wheel_base : kWheelBase;
    const double wheel_radius = drive.wheel_radius > 0 ? drive.wheel_radius : kWheelRadius;
    r->pull_limit = treel_max_torque_ / wheel_radius / (0.5 * total * std::max(gravity_.norm(), 1e-9));
    InsertSorted(robots_, r);

    // Chassis: the round body, the belly and the treels' wheels, one body.
    const double chassis_mass = total - (manip ? kHeadMass : 0.0);
    dBodyID chassis = MakeBody(s, com);
    dMass m;
    dMassSetCylinderTotal(&m, chassis_mass, 3, radius, height);
    dBodySetMass(chassis, &m);
    slot.space = dSimpleSpaceCreate(space_);
    dGeomID body = AddGeom(slot, dCreateCylinder(slot.space, radius, height - geo.body_bottom), s, kBody);
    dGeomSetBody(body, chassis);
    dGeomSetOffsetPosition(body, 0, 0, 0.5 * (height + geo.body_bottom) - com);
    dGeomID belly = AddGeom(slot,
                            dCreateBox(slot.space, 2 * geo.belly_half_length, 2 * geo.belly_half_width,
                                       geo.belly_top - geo.belly_bottom),
                            s, kBody);
    dGeomSetBody(belly, chassis);
    dGeomSetOffsetPosition(belly, 0, 0, 0.5 * (geo.belly_top + geo.belly_bottom) - com);
    // Treels: two wheels each (front and rear), whose tread moves at the
    // treel's speed.
    for (int k = 0; k < 4; ++k) {
      const int side = k / 2;  // 0 left (+y), 1 right (-y)
      dGeomID w = AddGeom(slot, dCreateSphere(slot.space, geo.treel_wheel_radius), s,
                          side == 0 ? kLeftTreel : kRightTreel);
      dGeomSetBody(w, chassis);
      dGeomSetOffsetPosition(w, k % 2 == 0 ? geo.treel_half_span : -geo.treel_half_span,
                             side == 0 ? geo.treel_y : -geo.treel_y, geo.treel_wheel_radius - com);
    }
    if (!manip) return;
    const Quat& q = pose.orientation;
    // The manipulator: the head on a vertical piston joint through its centre
    // (slides up and down, turns about it), both motions motor-driven.
    const Vec3 up = q * Vec3::UnitZ();
    r->elevation0 = std::clamp(manip->elevation, manip->min_elevation, manip->max_elevation);
    r->rotation0 = manip->rotation;
    const Vec3 arm = q * Vec3(kHeadPivotX, 0, r->elevation0);
    const Vec3 centre = pose.position + arm;
    r->head = dBodyCreate(world_);
    PlaceBody(r->head, centre, q * FromYaw(r->rotation0));
    SetBodyVelocity(r->head, twist.linear + twist.angular.cross(arm), twist.angular);
    dMass hm;
    // Inertia of a 10 cm cube of the head's mass: ODE's iterative solver
    // copes badly with a tiny body jointed to a large one.
    dMassSetBoxTotal(&hm, kHeadMass, 0.1, 0.1, 0.1);
    dBodySetMass(r->head, &hm);
    dGeomID head = AddGeom(slot, dCreateBox(slot.space, kHeadDepth, kHeadWidth, kHeadHeight), s, kBody);
    dGeomSetBody(head, r->head);
    r->piston = dJointCreatePiston(world_, nullptr);
    dJointAttach(r->piston, r->head, chassis);
    dJointSetPistonAnchor(r->piston, centre.x(), centre.y(), centre.z());
    dJointSetPistonAxis(r->piston, up.x(), up.y(), up.z());
    dJointSetPistonParam(r->piston, dParamFMax, kHeadMaxForce);
    dJointSetPistonParam(r->piston, dParamFMax2, kHeadMaxTorque);
  }

  template <class T>
  static void InsertSorted(std::vector<T>& list, T item) {
    auto key = [](const T& x) {
      if constexpr (std::is_pointer_v<T>) {
        return x->slot;
      } else {
        return x;
      }
    };
    auto it = std::lower_bound(list.begin(), list.end(), item,
                               [&](const T& a, const T& b) { return key(a) < key(b); });
    list.insert(it, item);
  }

  // The floor: a plane, or boxes around the ditches with the ditch bottoms
  // `depth` lower. The floor reaches 1 m beyond the arena on every side.
  void BuildFloor(const Space& space) {
    floor_built_ = true;
    const double z = space.arena_min().z();
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
        dGeomSetPosition(box, 0.5 * (xs[i] + xs[i1 + 1]), 0.5 * (ys[j] + ys[j1 + 1]), z - dd - 0.5 * kThickness);
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
    if (oa == ob && oa != kNone) return;  // parts of one robot
    if (ba && bb && dAreConnectedExcluding(ba, bb, dJointTypeContact)) return;
    // A held cube does not collide with the robot holding it.
    if (oa != kNone && ob != kNone && (slots_[oa].held_by == ob || slots_[ob].held_by == oa)) return;
    constexpr int kMax = 8;
    dContact contact[kMax];
    const int n = dCollide(a, b, kMax, &contact[0].geom, sizeof(dContact));
    if (n == 0) return;
    const Material ma = MaterialOf(a), mb = MaterialOf(b);
    const double mu = std::min(friction_[ma], friction_[mb]);
    // A treel touching something other than another treel drives it.
    dGeomID wheel = nullptr;
    if (ma == kTreel && mb != kTreel) wheel = a;
    if (mb == kTreel && ma != kTreel) wheel = b;
    double tread = 0, pull = mu;
    Vec3 axle = Vec3::Zero(), hub = Vec3::Zero();
    if (wheel) {
      const Robot& r = *slots_[OwnerOf(wheel)].robot;
      tread = r.tread[TagOf(wheel) == kRightTreel ? 1 : 0];
      const dReal* R = dBodyGetRotation(dGeomGetBody(wheel));
      axle = Vec3(R[1], R[5], R[9]);
      hub = ToVec(dGeomGetPosition(wheel));
      // The motor's torque bounds the pull along the tread: with the treel's
      // share of the robot's weight, F <= min(mu N, torque / wheel radius).
      pull = std::min(mu, r.pull_limit);
    }
    for (int i = 0; i < n; ++i) {
      dContact& c = contact[i];
      c.surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
      c.surface.mu = mu;
      c.surface.soft_erp = erp_;
      c.surface.soft_cfm = cfm_;
      if (!wheel) continue;
      const Vec3 normal = ToVec(c.geom.normal);
      Vec3 dir = axle.cross(normal);
      if (dir.squaredNorm() < 1e-12) continue;  // touching the wheel's side
      dir.normalize();
      // Velocity of the tread at the contact, relative to the chassis: the
      // wheel's rim turning about its axle at the tread's speed.
      const Vec3 arm = (ToVec(c.geom.pos) - hub).normalized();
      const double surface = tread * axle.cross(arm).dot(dir);
      // Sideways the tread yields a little under load (force-dependent slip):
      // with Coulomb friction alone, which of the front and rear wheels
      // slides when the robot turns would be arbitrary (the robot would turn
      // about its front or rear axle); this makes it turn about its middle,
      // as differential drive kinematics have it.
      c.surface.mode |= dContactFDir1 | dContactMu2 | dContactMotion1 | dContactSlip2;
      c.surface.mu = pull;
      c.surface.mu2 = mu;
      c.surface.slip2 = kTreelSideSlip;
      c.fdir1[0] = dir.x();
      c.fdir1[1] = dir.y();
      c.fdir1[2] = dir.z();
      // The constraint sets (velocity of body 1 - velocity of body 2) along
      // fdir1; a tread that does not slip moves the chassis against its own
      // motion.
      c.surface.motion1 = wheel == a ? -surface : surface;
    }
    for (int i = 0; i < n; ++i) {
      dJointID j = dJointCreateContact(world_, contacts_, &contact[i]);
      dJointAttach(j, ba, bb);
    }
    // Touching anything but the floor counts as a contact.
    if (ma != kGround && mb != kGround) {
      if (oa != kNone) touched_[oa] = 1;
      if (ob != kNone) touched_[ob] = 1;
    }
    if (ma == kCube && mb == kCube && ba && bb) touches_.emplace_back(std::min(oa, ob), std::max(oa, ob));
  }

  // -------------------------------------------------------------------------
  // Treels.
  // The commanded wheel speeds ask for forwards speed (l + r) / 2 and turn
  // rate (r - l) / wheel_base; the treads at y = +-treel_y give exactly that.
  void SetTreads(const Space& space, Robot& r) {
    const DriveState& d = *space.drive(r.slot);
    const double left = std::isfinite(d.left) ? d.left : 0.0;
    const double right = std::isfinite(d.right) ? d.right : 0.0;
    const double v = 0.5 * (left + right), w = (right - left) / r.wheel_base;
    r.tread[0] = v - w * kMarxbot3d.treel_y;
    r.tread[1] = v + w * kMarxbot3d.treel_y;
  }

  // -------------------------------------------------------------------------
  // Manipulator.
  double Elevation(const Robot& r) const { return r.elevation0 + dJointGetPistonPosition(r.piston); }
  double Rotation(const Robot& r) const { return WrapAngle(r.rotation0 + dJointGetPistonAngle(r.piston)); }

  void DriveHead(const Space& space, Robot& r, double h) {
    const ManipulatorState& m = *space.Get<ManipulatorState>(r.slot);
    const double lo = std::min(m.min_elevation, m.max_elevation), hi = std::max(m.min_elevation, m.max_elevation);
    const double target = std::clamp(std::isfinite(m.target_elevation) ? m.target_elevation : lo, lo, hi);
    const double e = Elevation(r);
    dJointSetPistonParam(r.piston, dParamVel, std::clamp((target - e) / h, -m.elevation_speed, m.elevation_speed));
    // Stops 1 cm beyond the range, so the motor never pushes against them (at
    // a stop ODE would add the motor's full force explicitly).
    dJointSetPistonParam(r.piston, dParamLoStop, lo - 0.01 - r.elevation0);
    dJointSetPistonParam(r.piston, dParamHiStop, hi + 0.01 - r.elevation0);
    const double aim = std::isfinite(m.target_rotation) ? m.target_rotation : Rotation(r);
    const double error = WrapAngle(aim - Rotation(r));
    dJointSetPistonParam(r.piston, dParamVel2, std::clamp(error / h, -m.rotation_speed, m.rotation_speed));
  }

  // Switches the magnet over, lets go when it is no longer fully engaged,
  // and holds what it touches when it is.
  void UpdateMagnet(Space& space, Robot& r, double dt) {
    ManipulatorState& m = *space.Get<ManipulatorState>(r.slot);
    const double step = m.switch_time > 0 ? dt / m.switch_time : 1.0;
    m.magnet = std::clamp(m.magnet + (m.want_magnet ? step : -step), 0.0, 1.0);
    // Summing dt / switch_time falls short of 1 (or 0) by a rounding error:
    // snap, so the switch takes switch_time, not a tick more.
    if (m.magnet > 1.0 - 1e-9) m.magnet = 1.0;
    if (m.magnet < 1e-9) m.magnet = 0.0;
    if (m.magnet < 1.0) {
      if (r.magnet_joint) Release(r);
      return;
    }
    if (!r.magnet_joint) Grab(space, r);
  }

  // The magnet face: centre and outward normal, world frame.
  void MagnetFace(const Robot& r, Vec3& centre, Vec3& normal) const {
    const Quat q = BodyQuat(r.head);
    normal = q * Vec3::UnitX();
    centre = BodyPos(r.head) + 0.5 * kHeadDepth * normal;
  }

  void Grab(const Space& space, Robot& r) {
    Vec3 centre, normal;
    MagnetFace(r, centre, normal);
    uint32_t best = kNone;
    double best_gap = 0;
    for (uint32_t c : cubes_) {
      const Slot& cube = slots_[c];
      if (cube.held_by != kNone || !cube.body) continue;
      const double side = space.geometry(c).size.x();
      const Quat qc = BodyQuat(cube.body);
      const Vec3 p = qc.conjugate() * (centre - BodyPos(cube.body));  // cube frame, from its centre
      const Vec3 n = qc.conjugate() * normal;
      // The side face the magnet is in front of.
      const int axis = std::abs(p.x()) >= std::abs(p.y()) ? 0 : 1;
      const double sign = p[axis] >= 0 ? 1.0 : -1.0;
      const double gap = sign * p[axis] - 0.5 * side;
      if (gap < -0.005 || gap > magnet_reach_) continue;
      if (-sign * n[axis] < kMagnetAlignment) continue;        // faces about parallel, facing each other
      if (std::abs(p[1 - axis]) > 0.5 * side) continue;        // over the face
      // Overlapping the plate: the lower half of the side.
      if (p.z() - 0.5 * kHeadHeight > 0 || p.z() + 0.5 * kHeadHeight < -0.5 * side) continue;
      if (best == kNone || gap < best_gap) {
        best = c;
        best_gap = gap;
      }
    }
    if (best == kNone) return;
    r.magnet_joint = dJointCreateFixed(world_, nullptr);
    dJointAttach(r.magnet_joint, r.head, slots_[best].body);
    dJointSetFixed(r.magnet_joint);
    dJointSetFeedback(r.magnet_joint, &r.magnet_feedback);
    r.held = best;
    slots_[best].held_by = r.slot;
  }

  void Release(Robot& r) {
    if (r.magnet_joint) dJointDestroy(r.magnet_joint);
    r.magnet_joint = nullptr;
    if (r.held != kNone) slots_[r.held].held_by = kNone;
    r.held = kNone;
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
      if (std::abs(d.z() - rest) > 0.01) continue;                        // not on its top
      const Quat rel = ql.conjugate() * BodyQuat(bu);
      if ((rel * Vec3::UnitZ()).z() < std::cos(cube_capture_angle_)) continue;  // tilted
      if (std::abs(d.x()) > cube_capture_ || std::abs(d.y()) > cube_capture_) continue;
      const Vec3 xr = rel * Vec3::UnitX();
      const double quarter = std::round(std::atan2(xr.y(), xr.x()) / (M_PI / 2)) * (M_PI / 2);
      if (std::abs(WrapAngle(std::atan2(xr.y(), xr.x()) - quarter)) > cube_capture_angle_) continue;
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

  // Magnets and bonds let go when pulled harder than their limit.
  void CheckBreaks() {
    for (Robot* r : robots_) {
      if (r->magnet_joint && ToVec(r->magnet_feedback.f2).norm() > magnet_max_force_) Release(*r);
    }
    for (size_t k = bonds_.size(); k-- > 0;) {
      if (ToVec(bonds_[k].feedback->f1).norm() > cube_bond_force_) Unbond(k);
    }
  }

  static void StopIfFallen(dBodyID body, dBodyID head, double bottom) {
    if (!dBodyIsEnabled(body) || dBodyGetPosition(body)[2] > bottom) return;
    dBodyDisable(body);
    SetBodyVelocity(body, Vec3::Zero(), Vec3::Zero());
    if (head) {
      dBodyDisable(head);
      SetBodyVelocity(head, Vec3::Zero(), Vec3::Zero());
    }
  }

  // -------------------------------------------------------------------------
  // Write-back.
  void WriteBody(Space& space, uint32_t s) {
    const Slot& slot = slots_[s];
    const Quat q = BodyQuat(slot.body);
    const Vec3 origin = BodyPos(slot.body) - q * Up(slot.com_height);
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

  void WriteRobot(Space& space, Robot& r, double dt) {
    WriteBody(space, r.slot);
    // The motors hold the treads at their speed (slip happens between tread
    // and ground), so the encoders count the commanded wheel speeds.
    DriveState& d = *space.drive(r.slot);
    d.travelled_left = (std::isfinite(d.left) ? d.left : 0.0) * dt;
    d.travelled_right = (std::isfinite(d.right) ? d.right : 0.0) * dt;
    if (!r.head) return;
    ManipulatorState& m = *space.Get<ManipulatorState>(r.slot);
    m.elevation = Elevation(r);
    m.rotation = Rotation(r);
    m.held = r.held;
  }

  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr, static_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  bool floor_built_ = false;
  unsigned long random_seed_ = 0;

  std::vector<Slot> slots_;             // per space slot
  std::vector<uint8_t> touched_;        // per space slot: a contact this tick
  std::vector<Robot*> robots_;          // in slot order
  std::vector<uint32_t> objects_;       // movable non-robot slots, in order
  std::vector<uint32_t> cubes_;         // movable cubes, in order
  std::vector<std::pair<uint32_t, uint32_t>> touches_;  // cube pairs in contact this sub-step
  std::vector<Bond> bonds_;

  Vec3 gravity_ = Vec3(0, 0, -9.81);
  bool quickstep_ = true;
  int iterations_ = 20, substeps_ = 10;
  double erp_ = 0.2, cfm_ = 1e-5;
  std::array<double, kMaterials> friction_ = {1.0, 0.6, 0.3, 0.5, 0.5};
  double treel_max_torque_ = 0.22, magnet_max_force_ = 2.0, magnet_reach_ = 0.01;
  double cube_capture_ = 0.02, cube_capture_angle_ = 0.35, cube_bond_force_ = 2.0;
};

COLONY_REGISTER_ENGINE(
    Dynamics3dEngine, "dynamics3d",
    "3D rigid-body dynamics (ODE): gravity, floors with ditches, the marXbot on motor-driven treels, its "
    "construction manipulator and magnet, self-aligning construction cubes",
    (std::vector<AttributeDoc>{
        {"gravity", "\"x,y,z\" (m/s^2)", "0,0,-9.81", "gravity"},
        {"stepper", "quickstep, worldstep", "quickstep",
         "ODE's iterative solver (cost linear in the contacts) or its exact one (per island of touching "
         "bodies, cost cubic in the island's size)"},
        {"iterations", "a whole number in [1, 1000]", "20", "quickstep iterations per sub-step"},
        {"substeps", "a whole number in [1, 1000]", "10", "physics sub-steps per tick"},
        {"erp", "a number in [0, 1]", "0.2", "share of joint and contact error corrected per sub-step"},
        {"cfm", "a number >= 0", "1e-05", "constraint force mixing (softness of joints and contacts)"},
        {"ground_friction", "a number >= 0", "1", "friction coefficient of the floor and ditches"},
        {"treel_friction", "a number >= 0", "0.6", "friction coefficient of the treels (rubber)"},
        {"body_friction", "a number >= 0", "0.3", "friction coefficient of robot bodies and the manipulator head"},
        {"cube_friction", "a number >= 0", "0.5", "friction coefficient of construction cubes"},
        {"object_friction", "a number >= 0", "0.5", "friction coefficient of boxes, cylinders and walls"},
        {"treel_max_torque", "a number > 0 (N m)", "0.22",
         "most torque a treel's motor gives: the treel pushes at most this / wheel radius"},
        {"magnet_max_force", "a number > 0 (N)", "2", "force beyond which the magnet lets go of what it holds"},
        {"magnet_reach", "a number >= 0 (m)", "0.01", "largest gap between magnet and cube side for a grip"},
        {"cube_capture", "a number >= 0 (m)", "0.02",
         "largest horizontal offset at which a cube landing on another aligns with it (0: never)"},
        {"cube_capture_angle", "a number in [0, 0.785] (rad)", "0.35",
         "largest turn from the cube below at which a landing cube aligns with it"},
        {"cube_bond_force", "a number > 0 (N)", "2", "force beyond which two stacked cubes come apart"},
    }));

}  // namespace
}  // namespace colony
