// dynamics2d: top-down 2D rigid-body dynamics on Box2D 2.4.
//
// The floor is the plane of the world (no gravity in it). Objects slide on it
// against friction, modelled by a friction joint to a fixed ground body whose
// maximum force is floor_friction x m x g. Every entity is one body of its
// footprint: fixed ones static bodies nothing can move, movable ones dynamic
// bodies of their mass. The engine knows no robot: each entity type's model
// (dynamics2d.h) adds what the type needs, composing the pieces there: floor
// friction for objects, treels (force- and torque-limited differential drive
// that slips when it pushes too hard) and a weld gripper for the marXbot
// (entities/marxbot/dynamics2d_model.cpp).
#include "engines/dynamics2d/dynamics2d.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <memory>
#include <vector>

#include "actuators/gripper/gripper_state.h"
#include "core/simulation.h"

namespace colony {
namespace dynamics2d {

Space& Engine::entities() { return sim().space(); }

void Engine::AddFloorFriction(uint32_t s) {
  const Space& space = sim().space();
  b2Body* body = bodies_[s];
  const double mass = space.mass(s) > 0 ? space.mass(s) : 1.0;
  b2FrictionJointDef joint;
  joint.Initialize(ground_, body, body->GetWorldCenter());
  const double weight = params_.floor_friction * mass * kGravity;
  joint.maxForce = static_cast<float>(weight);
  joint.maxTorque = static_cast<float>(weight * 0.5 * space.geometry(s).BoundingRadius());
  world_->CreateJoint(&joint);
}

uint32_t Engine::MovableAt(const b2Vec2& p, const b2Body* self) {
  struct Query : b2QueryCallback {
    b2Vec2 point;
    const b2Body* self;
    uint32_t found = kNone;
    bool ReportFixture(b2Fixture* f) override {
      b2Body* b = f->GetBody();
      if (b != self && b->GetType() == b2_dynamicBody && f->TestPoint(point)) {
        found = std::min(found, static_cast<uint32_t>(b->GetUserData().pointer));
      }
      return true;
    }
  } query;
  query.point = p;
  query.self = self;
  b2AABB box;
  box.lowerBound = p - b2Vec2(0.001f, 0.001f);
  box.upperBound = p + b2Vec2(0.001f, 0.001f);
  world_->QueryAABB(&query, box);
  return query.found;
}

// ---------------------------------------------------------------------------
// Treels.

void Treels::Add(Engine& engine, uint32_t s) {
  engine.BodyOf(s)->SetSleepingAllowed(false);
  slots_.push_back(s);
  headings_.emplace_back();
}

void Treels::Remove(uint32_t s) {
  auto it = std::find(slots_.begin(), slots_.end(), s);
  if (it == slots_.end()) return;
  headings_.erase(headings_.begin() + (it - slots_.begin()));
  slots_.erase(it);
}

const Treels::Heading& Treels::HeadingOf(size_t k, float angle) {
  Heading& h = headings_[k];
  const uint32_t bits = std::bit_cast<uint32_t>(angle);
  if (!h.known || bits != h.angle_bits) {
    h.known = true;
    h.angle_bits = bits;
    h.cos = std::cos(static_cast<double>(angle));
    h.sin = std::sin(static_cast<double>(angle));
  }
  return h;
}

void Treels::Drive(Engine& engine, double h) {
  const Space& space = engine.entities();
  const double max_force = engine.params().robot_max_force;
  const double max_torque = engine.params().robot_max_torque;
  for (size_t k = 0; k < slots_.size(); ++k) {
    const uint32_t s = slots_[k];
    b2Body* body = engine.BodyOf(s);
    const DriveState& d = *space.drive(s);
    const double v = 0.5 * (d.left + d.right);
    const double w = (d.right - d.left) / d.wheel_base;
    const Heading& heading = HeadingOf(k, body->GetAngle());
    const b2Vec2 vel = body->GetLinearVelocity();
    const double m = body->GetMass();
    double fx = m * (v * heading.cos - vel.x) / h;
    double fy = m * (v * heading.sin - vel.y) / h;
    // Most robots push far below the limit: the square, with room for its
    // rounding, settles those without the (slow, exact) hypot.
    if (fx * fx + fy * fy > max_force * max_force * (1 - 1e-9)) {
      const double f = std::hypot(fx, fy);
      if (f > max_force) {
        fx *= max_force / f;
        fy *= max_force / f;
      }
    }
    const double torque = std::clamp(body->GetInertia() * (w - body->GetAngularVelocity()) / h,
                                     -max_torque, max_torque);
    body->ApplyForceToCenter(b2Vec2(static_cast<float>(fx), static_cast<float>(fy)), true);
    body->ApplyTorque(static_cast<float>(torque), true);
  }
}

void Treels::WriteOdometry(Engine& engine, double dt) {
  Space& space = engine.entities();
  for (size_t k = 0; k < slots_.size(); ++k) {
    const uint32_t s = slots_[k];
    const b2Body* body = engine.BodyOf(s);
    const b2Vec2 v = body->GetLinearVelocity();
    const Heading& heading = HeadingOf(k, body->GetAngle());
    const double w = body->GetAngularVelocity();
    // What the treels really did: forwards speed and turn rate of the body.
    DriveState& d = *space.drive(s);
    const double forward = v.x * heading.cos + v.y * heading.sin;
    d.travelled_left = (forward - 0.5 * w * d.wheel_base) * dt;
    d.travelled_right = (forward + 0.5 * w * d.wheel_base) * dt;
  }
}

// ---------------------------------------------------------------------------
// Weld gripper.

void WeldGripper::Update(Engine& engine, const std::vector<uint32_t>& robots) {
  Space& space = engine.entities();
  for (size_t k = grips_.size(); k-- > 0;) {
    if (!space.Get<GripperState>(grips_[k].robot)->want_grip) Ungrip(engine, k);
  }
  for (uint32_t s : robots) {
    GripperState* g = space.Get<GripperState>(s);
    if (!g || !g->want_grip || g->holding()) continue;
    b2Body* body = engine.BodyOf(s);
    const double angle = body->GetAngle() + g->turret;
    const b2Vec2 dir(static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)));
    const float radius = static_cast<float>(space.geometry(s).radius);
    // The jaws close on the nearest body within reach, the lowest slot first.
    for (int step = 1; step <= 4 && !g->holding(); ++step) {
      const b2Vec2 p =
          body->GetPosition() + (radius + static_cast<float>(g->reach * step / 4)) * dir;
      const uint32_t target = engine.MovableAt(p, body);
      if (target == kNone) continue;
      b2WeldJointDef joint;
      joint.Initialize(body, engine.BodyOf(target), p);
      grips_.push_back({s, target, engine.world().CreateJoint(&joint)});
      g->held = target;
    }
  }
}

void WeldGripper::Forget(Engine& engine, uint32_t s) {
  for (size_t k = grips_.size(); k-- > 0;) {
    if (grips_[k].robot == s || grips_[k].target == s) Ungrip(engine, k);
  }
}

void WeldGripper::Ungrip(Engine& engine, size_t k) {
  engine.world().DestroyJoint(grips_[k].joint);
  if (GripperState* g = engine.entities().Get<GripperState>(grips_[k].robot)) g->held = kNone;
  grips_.erase(grips_.begin() + static_cast<std::ptrdiff_t>(k));
}

// ---------------------------------------------------------------------------
namespace {

class Dynamics2dEngine : public Engine {
 public:
  Dynamics2dEngine() {
    world_ = std::make_unique<b2World>(b2Vec2(0.0f, 0.0f));
    b2BodyDef ground;
    ground_ = world_->CreateBody(&ground);
  }

  void Configure(const ConfigNode& node) override {
    velocity_iterations_ = static_cast<int>(node.GetInt("iterations", 8, 1, 1000));
    position_iterations_ = static_cast<int>(node.GetInt("position_iterations", 3, 1, 1000));
    substeps_ = static_cast<int>(node.GetInt("substeps", 2, 1, 1000));
    params_.friction = node.GetDouble("friction", 0.5, Range::NonNegative());
    params_.floor_friction = node.GetDouble("floor_friction", 0.5, Range::NonNegative());
    params_.robot_max_force = node.GetDouble("robot_max_force", 15.0, Range::Positive());
    params_.robot_max_torque = node.GetDouble("robot_max_torque", 1.5, Range::Positive());
  }

  void AddEntity(EntityHandle entity, PhysicsModel& physics_model) override {
    auto& model = dynamic_cast<Dynamics2dModel&>(physics_model);
    Space& space = sim().space();
    const uint32_t s = entity.index;
    const Pose& pose = space.pose(s);
    const Twist& twist = space.twist(s);
    const Geometry& g = space.geometry(s);
    const bool movable = space.movable(s);

    b2BodyDef def;
    def.type = movable ? b2_dynamicBody : b2_staticBody;
    def.position.Set(static_cast<float>(pose.position.x()), static_cast<float>(pose.position.y()));
    def.angle = static_cast<float>(YawOf(pose.orientation));
    def.linearVelocity.Set(static_cast<float>(twist.linear.x()),
                           static_cast<float>(twist.linear.y()));
    def.angularVelocity = static_cast<float>(twist.angular.z());
    def.userData.pointer = s;
    b2Body* body = world_->CreateBody(&def);

    b2CircleShape circle;
    b2PolygonShape box;
    b2FixtureDef fixture;
    double area;
    if (g.shape == ShapeKind::kBox) {
      box.SetAsBox(static_cast<float>(0.5 * g.size.x()), static_cast<float>(0.5 * g.size.y()));
      fixture.shape = &box;
      area = g.size.x() * g.size.y();
    } else {
      circle.m_radius = static_cast<float>(g.radius);
      fixture.shape = &circle;
      area = M_PI * g.radius * g.radius;
    }
    const double mass = space.mass(s) > 0 ? space.mass(s) : 1.0;
    fixture.density = movable ? static_cast<float>(mass / area) : 0.0f;
    fixture.friction = static_cast<float>(params_.friction);
    body->CreateFixture(&fixture);

    if (bodies_.size() <= s) {
      bodies_.resize(s + 1, nullptr);
      models_of_.resize(s + 1, nullptr);
    }
    bodies_[s] = body;
    models_of_[s] = &model;
    if (std::find(models_.begin(), models_.end(), &model) == models_.end())
      models_.push_back(&model);
    if (!movable) return;
    model.Add(*this, s);
    movables_.push_back(s);
  }

  void RemoveEntity(EntityHandle entity) override {
    const uint32_t s = entity.index;
    if (s >= bodies_.size() || !bodies_[s]) return;
    for (Dynamics2dModel* m : models_) m->EntityLeaving(*this, s);
    if (sim().space().movable(s)) models_of_[s]->Remove(*this, s);
    world_->DestroyBody(bodies_[s]);  // its joints go with it
    bodies_[s] = nullptr;
    models_of_[s] = nullptr;
    auto it = std::find(movables_.begin(), movables_.end(), s);
    if (it != movables_.end()) movables_.erase(it);
  }

  void Step(double dt) override {
    Space& space = sim().space();
    const double h = dt / substeps_;
    for (Dynamics2dModel* m : models_) m->BeforeStep(*this, dt);
    for (int k = 0; k < substeps_; ++k) {
      for (Dynamics2dModel* m : models_) m->BeforeSubstep(*this, h);
      world_->Step(static_cast<float>(h), velocity_iterations_, position_iterations_);
    }
    for (uint32_t s : movables_) WriteBack(space, s);
    for (Dynamics2dModel* m : models_) m->AfterStep(*this, dt);
  }

 private:
  void WriteBack(Space& space, uint32_t s) {
    const b2Body* body = bodies_[s];
    const b2Vec2 p = body->GetPosition();
    const b2Vec2 v = body->GetLinearVelocity();
    const double angle = body->GetAngle();
    const double w = body->GetAngularVelocity();
    Pose& pose = space.pose(s);
    pose.position.x() = p.x;
    pose.position.y() = p.y;
    pose.orientation = FromYaw(WrapAngle(angle));
    Twist& twist = space.twist(s);
    twist.linear = Vec3(v.x, v.y, 0);
    twist.angular = Vec3(0, 0, w);
    bool touching = false;
    for (const b2ContactEdge* c = body->GetContactList(); c && !touching; c = c->next) {
      touching = c->contact->IsTouching();
    }
    space.set_in_contact(s, touching);
  }

  std::vector<Dynamics2dModel*> models_;     // in the order their first entity came
  std::vector<Dynamics2dModel*> models_of_;  // per space slot
  std::vector<uint32_t> movables_;           // movable slots, in the order they came
  int velocity_iterations_ = 8, position_iterations_ = 3, substeps_ = 2;
};

COLONY_REGISTER_ENGINE(
    Dynamics2dEngine, "dynamics2d",
    "top-down 2D rigid-body dynamics (Box2D): robots push movable objects against floor friction; "
    "treels have a maximum force and torque, beyond which they slip",
    (std::vector<AttributeDoc>{
        {"iterations", "a whole number in [1, 1000]", "8",
         "Box2D velocity iterations per sub-step"},
        {"position_iterations", "a whole number in [1, 1000]", "3",
         "Box2D position iterations per sub-step"},
        {"substeps", "a whole number in [1, 1000]", "2", "physics sub-steps per tick"},
        {"friction", "a number >= 0", "0.5", "friction coefficient between bodies"},
        {"floor_friction", "a number >= 0", "0.5",
         "friction coefficient of objects sliding on the floor"},
        {"robot_max_force", "a number > 0 (N)", "15",
         "most force the treels exert before slipping"},
        {"robot_max_torque", "a number > 0 (N m)", "1.5",
         "most torque the treels exert before slipping"},
    }));

}  // namespace
}  // namespace dynamics2d
}  // namespace colony
