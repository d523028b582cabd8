// dynamics2d: top-down 2D rigid-body dynamics on Box2D 2.4.
//
// The floor is the plane of the world (no gravity in it). Objects slide on it
// against friction, modelled by a friction joint to a fixed ground body whose
// maximum force is floor_friction x m x g. A wheeled robot is a circular body
// driven towards the velocity its wheels command (forwards speed and turn
// rate, no sideways motion) by a force and a torque that cannot exceed
// robot_max_force and robot_max_torque: when it pushes too hard the wheels
// slip and it falls behind its command. Movable objects are pushed; fixed
// ones are static bodies nothing can move. A robot gripping welds the thing
// in front of its jaws (a movable object, another robot) to its body until it
// releases; a grip does not survive the robot or the held thing leaving this
// engine (migrating to another engine's region, or being removed).
#include <box2d/box2d.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "actuators/gripper/gripper_state.h"
#include "core/engine.h"
#include "core/simulation.h"

namespace colony {
namespace {

constexpr double kGravity = 9.81;

class Dynamics2dModel : public PhysicsModel {
 public:
  explicit Dynamics2dModel(bool wheeled) : wheeled_(wheeled) {}
  bool wheeled() const { return wheeled_; }

 private:
  bool wheeled_;
};

class WheeledRobotModel : public Dynamics2dModel {
 public:
  WheeledRobotModel() : Dynamics2dModel(true) {}
};

class ObjectModel : public Dynamics2dModel {
 public:
  ObjectModel() : Dynamics2dModel(false) {}
};

COLONY_REGISTER_PHYSICS_MODEL(
    WheeledRobotModel, "dynamics2d:marxbot",
    "circular body driven by force- and torque-limited treels (slip when pushing hard)",
    (std::vector<std::string>{"drive", "gripper"}));
COLONY_REGISTER_PHYSICS_MODEL(ObjectModel, "dynamics2d:box",
                              "box: pushed against floor friction if movable, static otherwise",
                              (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(
    ObjectModel, "dynamics2d:cylinder",
    "cylinder: pushed against floor friction if movable, static otherwise",
    (std::vector<std::string>{}));

class Dynamics2dEngine : public PhysicsEngine {
 public:
  Dynamics2dEngine() : world_(std::make_unique<b2World>(b2Vec2(0.0f, 0.0f))) {
    b2BodyDef ground;
    ground_ = world_->CreateBody(&ground);
  }

  void Configure(const ConfigNode& node) override {
    velocity_iterations_ = static_cast<int>(node.GetInt("iterations", 8, 1, 1000));
    position_iterations_ = static_cast<int>(node.GetInt("position_iterations", 3, 1, 1000));
    substeps_ = static_cast<int>(node.GetInt("substeps", 2, 1, 1000));
    friction_ = node.GetDouble("friction", 0.5, Range::NonNegative());
    floor_friction_ = node.GetDouble("floor_friction", 0.5, Range::NonNegative());
    max_force_ = node.GetDouble("robot_max_force", 15.0, Range::Positive());
    max_torque_ = node.GetDouble("robot_max_torque", 1.5, Range::Positive());
  }

  void AddEntity(EntityHandle entity, PhysicsModel& model) override {
    const auto& m = dynamic_cast<const Dynamics2dModel&>(model);
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
    fixture.friction = static_cast<float>(friction_);
    body->CreateFixture(&fixture);

    if (bodies_.size() <= s) bodies_.resize(s + 1, nullptr);
    bodies_[s] = body;
    if (!movable) return;
    if (m.wheeled() && space.drive(s)) {
      body->SetSleepingAllowed(false);
      robots_.push_back(s);
    } else {
      // Sliding on the floor: friction against a fixed ground body.
      b2FrictionJointDef joint;
      joint.Initialize(ground_, body, body->GetWorldCenter());
      const double weight = floor_friction_ * mass * kGravity;
      joint.maxForce = static_cast<float>(weight);
      joint.maxTorque = static_cast<float>(weight * 0.5 * g.BoundingRadius());
      world_->CreateJoint(&joint);
      objects_.push_back(s);
    }
  }

  void RemoveEntity(EntityHandle entity) override {
    const uint32_t s = entity.index;
    if (s >= bodies_.size() || !bodies_[s]) return;
    for (size_t k = grips_.size(); k-- > 0;) {
      if (grips_[k].robot == s || grips_[k].target == s) Ungrip(sim().space(), k);
    }
    world_->DestroyBody(bodies_[s]);  // its joints go with it
    bodies_[s] = nullptr;
    for (auto* list : {&robots_, &objects_}) {
      auto it = std::find(list->begin(), list->end(), s);
      if (it != list->end()) list->erase(it);
    }
  }

  void Step(double dt) override {
    Space& space = sim().space();
    const double h = dt / substeps_;
    UpdateGrips(space);
    for (int k = 0; k < substeps_; ++k) {
      for (uint32_t s : robots_) Drive(space, s, h);
      world_->Step(static_cast<float>(h), velocity_iterations_, position_iterations_);
    }
    for (uint32_t s : robots_) WriteBack(space, s, dt, true);
    for (uint32_t s : objects_) WriteBack(space, s, dt, false);
  }

 private:
  struct Grip {
    uint32_t robot, target;
    b2Joint* joint;
  };

  // Releases what robots no longer want to hold; grips what is in front of
  // the jaws of robots that want to hold something.
  void UpdateGrips(Space& space) {
    for (size_t k = grips_.size(); k-- > 0;) {
      if (!space.Get<GripperState>(grips_[k].robot)->want_grip) Ungrip(space, k);
    }
    for (uint32_t s : robots_) {
      GripperState* g = space.Get<GripperState>(s);
      if (!g || !g->want_grip || g->holding()) continue;
      b2Body* body = bodies_[s];
      const double angle = body->GetAngle() + g->turret;
      const b2Vec2 dir(static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)));
      const float radius = static_cast<float>(space.geometry(s).radius);
      // The jaws close on the nearest body within reach, the lowest slot first.
      for (int step = 1; step <= 4 && !g->holding(); ++step) {
        const b2Vec2 p =
            body->GetPosition() + (radius + static_cast<float>(g->reach * step / 4)) * dir;
        const uint32_t target = BodyAt(p, body);
        if (target == UINT32_MAX) continue;
        b2WeldJointDef joint;
        joint.Initialize(body, bodies_[target], p);
        grips_.push_back({s, target, world_->CreateJoint(&joint)});
        g->held = target;
      }
    }
  }

  // Slot of the lowest-slot movable body (not `self`) covering p, or UINT32_MAX.
  uint32_t BodyAt(const b2Vec2& p, const b2Body* self) {
    struct Query : b2QueryCallback {
      b2Vec2 point;
      const b2Body* self;
      uint32_t found = UINT32_MAX;
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

  void Ungrip(Space& space, size_t k) {
    world_->DestroyJoint(grips_[k].joint);
    if (GripperState* g = space.Get<GripperState>(grips_[k].robot)) g->held = 0xFFFFFFFFu;
    grips_.erase(grips_.begin() + static_cast<std::ptrdiff_t>(k));
  }

  // Force and torque towards the wheels' command, within the treels' limits.
  void Drive(Space& space, uint32_t s, double h) {
    b2Body* body = bodies_[s];
    const DriveState& d = *space.drive(s);
    const double v = 0.5 * (d.left + d.right);
    const double w = (d.right - d.left) / d.wheel_base;
    const double angle = body->GetAngle();
    const b2Vec2 vel = body->GetLinearVelocity();
    const double m = body->GetMass();
    double fx = m * (v * std::cos(angle) - vel.x) / h;
    double fy = m * (v * std::sin(angle) - vel.y) / h;
    const double f = std::hypot(fx, fy);
    if (f > max_force_) {
      fx *= max_force_ / f;
      fy *= max_force_ / f;
    }
    const double torque = std::clamp(body->GetInertia() * (w - body->GetAngularVelocity()) / h,
                                     -max_torque_, max_torque_);
    body->ApplyForceToCenter(b2Vec2(static_cast<float>(fx), static_cast<float>(fy)), true);
    body->ApplyTorque(static_cast<float>(torque), true);
  }

  void WriteBack(Space& space, uint32_t s, double dt, bool wheeled) {
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
    if (!wheeled) return;
    // What the treels really did: forwards speed and turn rate of the body.
    DriveState& d = *space.drive(s);
    const double forward = v.x * std::cos(angle) + v.y * std::sin(angle);
    d.travelled_left = (forward - 0.5 * w * d.wheel_base) * dt;
    d.travelled_right = (forward + 0.5 * w * d.wheel_base) * dt;
  }

  std::unique_ptr<b2World> world_;
  b2Body* ground_ = nullptr;
  std::vector<b2Body*> bodies_;    // per space slot
  std::vector<uint32_t> robots_;   // slots of wheeled robots, in the order they came
  std::vector<uint32_t> objects_;  // slots of movable objects
  std::vector<Grip> grips_;
  int velocity_iterations_ = 8, position_iterations_ = 3, substeps_ = 2;
  double friction_ = 0.5, floor_friction_ = 0.5, max_force_ = 15.0, max_torque_ = 1.5;
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
}  // namespace colony
