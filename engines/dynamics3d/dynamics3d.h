// dynamics3d's interface to the physics models of entity types
// (core/engine.h): the engine (ODE world, collision spaces, contacts, the
// floor and its ditches, construction cubes landing on cubes) knows no
// robot; a model builds its entity type's bodies, geoms and joints through
// the engine, drives its motors each (sub-)step, and writes its components
// back. Reusable pieces models compose (treels, a magnet) are in parts.h.
#pragma once

#include <ode/ode.h>

#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/engine.h"

namespace colony {
namespace dynamics3d {

inline constexpr uint32_t kNone = 0xFFFFFFFFu;

// Surface materials. A contact uses the smaller of its two materials'
// friction coefficients (the engine's *_friction attributes). Geoms of
// material kTread are moving surfaces: their model sets the contacts'
// surface motion (Dynamics3dModel::ModifyContacts). The ceiling has the
// friction of objects.
enum Material : uint8_t { kGround, kTread, kBody, kCube, kObject, kCeiling, kMaterials };

// Conversions between ODE and Colony.
inline Vec3 ToVec(const dReal* v) { return Vec3(v[0], v[1], v[2]); }
inline Quat ToQuat(const dReal* q) { return Quat(q[0], q[1], q[2], q[3]).normalized(); }
inline void SetQuat(dQuaternion out, const Quat& q) {
  out[0] = q.w();
  out[1] = q.x();
  out[2] = q.y();
  out[3] = q.z();
}
inline Quat BodyQuat(dBodyID b) { return ToQuat(dBodyGetQuaternion(b)); }
inline Vec3 BodyPos(dBodyID b) { return ToVec(dBodyGetPosition(b)); }
inline void PlaceBody(dBodyID b, const Vec3& p, const Quat& q) {
  dBodySetPosition(b, p.x(), p.y(), p.z());
  dQuaternion dq;
  SetQuat(dq, q);
  dBodySetQuaternion(b, dq);
}
inline void SetBodyVelocity(dBodyID b, const Vec3& v, const Vec3& w) {
  dBodySetLinearVel(b, v.x(), v.y(), v.z());
  dBodySetAngularVel(b, w.x(), w.y(), w.z());
}

// The engine's attributes, as models read them.
struct Params {
  Vec3 gravity = Vec3(0, 0, -9.81);
  double erp = 0.2, cfm = 1e-5;
  std::array<double, kMaterials> friction = {1.0, 0.6, 0.3, 0.5, 0.5, 0.5};
  double treel_max_torque = 0.22;  // N m, per treel motor
  double magnet_max_force = 2.0;   // N
  double magnet_reach = 0.01;      // m
  double cube_capture = 0.02, cube_capture_angle = 0.35, cube_bond_force = 2.0;
  bool quickstep = true;  // the stepper: quickstep (iterative) or worldstep (exact)
  int iterations = 20;    // quickstep's
};

class Engine;

}  // namespace dynamics3d

// How one entity type is simulated in dynamics3d. One instance per engine
// and type (core/engine.h): it keeps the entities it was given and steps
// them as a batch. Fixed entities need nothing from their model but the
// material of their static geometry; the engine builds it.
class Dynamics3dModel : public PhysicsModel {
 public:
  using Engine = dynamics3d::Engine;
  // Material of the entity's geometry when it is fixed.
  virtual dynamics3d::Material fixed_material() const { return dynamics3d::kObject; }
  // Builds movable entity `s`: its body (Engine::MakeBody), geoms and joints,
  // from its pose, velocity and components in the space (it may be
  // migrating in).
  virtual void Add(Engine& engine, uint32_t s) = 0;
  // Destroys the joints and part bodies it made for `s`, which is leaving the
  // engine; the engine then destroys the entity's geoms and main body.
  virtual void Remove(Engine& engine, uint32_t s) { (void)engine, (void)s; }
  // `holder` (one of this model's entities) must let go of `held`, which is
  // leaving the engine.
  virtual void Release(Engine& engine, uint32_t holder, uint32_t held) {
    (void)engine, (void)holder, (void)held;
  }
  // Each tick: before the sub-steps (commands into motors, grips), before
  // each sub-step (motors that track a target), after each sub-step's
  // solve (joints that break), and after the tick (components written back;
  // the engine has already written pose, velocity and contact).
  virtual void BeforeStep(Engine& engine, double dt) { (void)engine, (void)dt; }
  virtual void BeforeSubstep(Engine& engine, double h) { (void)engine, (void)h; }
  virtual void AfterSubstep(Engine& engine) { (void)engine; }
  virtual void AfterStep(Engine& engine, double dt) { (void)engine, (void)dt; }
  // Geom `surface` (material kTread, of one of this model's entities)
  // touches something else: contacts[0..n) have their friction mu and
  // softness set; the model adds the surface's motion. `surface_first`:
  // whether `surface` is the contacts' first geom.
  virtual void ModifyContacts(Engine& engine, dGeomID surface, bool surface_first, double mu,
                              dContact* contacts, int n) {
    (void)engine, (void)surface, (void)surface_first, (void)mu, (void)contacts, (void)n;
  }
};

namespace dynamics3d {

// What the engine offers its models.
class Engine : public PhysicsEngine {
 public:
  const Params& params() const { return params_; }
  dWorldID world() const { return world_; }
  Space& entities();

  // Creates the main body of `s` at the entity's pose and velocity, its origin
  // com_height above the entity's origin (in the entity's frame), or at
  // `com` from it (a centre of mass off the entity's axis).
  dBodyID MakeBody(uint32_t s, double com_height);
  dBodyID MakeBody(uint32_t s, const Vec3& com);
  dBodyID BodyOf(uint32_t s) const { return s < slots_.size() ? slots_[s].body : nullptr; }
  // A body of another part of `s` (a manipulator's head): stopped with the
  // main body when it falls off the floor. The model destroys it.
  void AddPartBody(uint32_t s, dBodyID body) { slots_[s].parts.push_back(body); }
  // A collision space for the parts of `s`, which never collide with one
  // another.
  dSpaceID MakePartSpace(uint32_t s);
  // Registers geom `g` of `s`, of material `m`; `part` (0-31) is the model's
  // own tag (PartOf) for telling its geoms apart in ModifyContacts.
  dGeomID AddGeom(uint32_t s, dGeomID g, Material m, uint8_t part = 0);
  // The entity's own geometry (a box or an upright cylinder) as one solid
  // body of its mass; kCube makes it a construction cube.
  void AddSolid(uint32_t s, Material m);
  static uint32_t OwnerOf(dGeomID g);
  static uint8_t PartOf(dGeomID g);

  // What a ray met: its distance along the ray, the point, the material and
  // the owner (kNone for the floor and the ceiling).
  struct RayHit {
    double distance = 0;
    Vec3 point = Vec3::Zero();
    Material material = kGround;
    uint32_t owner = kNone;
  };
  // The nearest geom (fixed or movable, not one of `ignore`'s) a ray from
  // `from` along the unit vector `direction` meets within `length`; false if
  // none. Builds the floor and ceiling first if the engine has not stepped.
  bool CastRay(const Vec3& from, const Vec3& direction, double length, uint32_t ignore,
               RayHit& hit);

  // What a sphere touches: the geom with the lowest owner slot (kNone, the
  // floor and the ceiling, last) that overlaps the sphere of `radius` at
  // `centre`, not one of `ignore`'s; its body is null for fixed things.
  struct Touch {
    dGeomID geom = nullptr;
    dBodyID body = nullptr;
    uint32_t owner = kNone;
    Material material = kGround;
  };
  bool TouchAt(const Vec3& centre, double radius, uint32_t ignore, Touch& touch);

  // Movable construction cubes, in slot order.
  const std::vector<uint32_t>& cubes() const { return cubes_; }
  // The entity holding `s` (kNone: none). A held entity does not collide with
  // its holder, does not bond to cubes, and when it leaves the engine its
  // holder's model is told to let go (Dynamics3dModel::Release).
  uint32_t HolderOf(uint32_t s) const { return slots_[s].held_by; }
  void SetHolder(uint32_t s, uint32_t holder) { slots_[s].held_by = holder; }

 protected:
  struct Slot {
    Dynamics3dModel* model = nullptr;
    dBodyID body = nullptr;
    dSpaceID space = nullptr;  // the space of its parts, if any
    std::vector<dGeomID> geoms;
    std::vector<dBodyID> parts;  // part bodies beside the main one
    Vec3 com =
        Vec3::Zero();  // body origin (centre of mass) from the entity's origin, in its frame (m)
    uint32_t held_by = kNone;
  };

  virtual void BuildFloor(const Space& space) = 0;
  bool floor_built_ = false;
  Params params_;
  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr, static_ = nullptr;
  std::vector<Slot> slots_;         // per space slot
  std::vector<uint32_t> cubes_;     // movable cubes, in slot order
  std::vector<uint32_t> movables_;  // movable entities, in slot order
};

}  // namespace dynamics3d
}  // namespace colony
