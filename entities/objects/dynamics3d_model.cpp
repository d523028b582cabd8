// Boxes, cylinders and construction cubes in dynamics3d
// (engines/dynamics3d): a solid body of the entity's geometry and mass if
// movable, static geometry otherwise. Cubes are the engine's construction
// cubes: magnets hold them, and one landing on another bonds to it.
// Landmarks are static cylinders. Pockets are kinematic bodies: robots stop
// at them and cannot push them, gravity does not move them; each lies where
// the space puts it (the heap model settles it, entities/objects/README.md).
#include <algorithm>
#include <vector>

#include "engines/dynamics3d/dynamics3d.h"

namespace colony {
namespace {

class SolidDynamics3dModel : public Dynamics3dModel {
 public:
  explicit SolidDynamics3dModel(dynamics3d::Material material) : material_(material) {}
  dynamics3d::Material fixed_material() const override { return material_; }
  void Add(Engine& engine, uint32_t s) override { engine.AddSolid(s, material_); }

 private:
  dynamics3d::Material material_;
};

class BoxModel : public SolidDynamics3dModel {
 public:
  BoxModel() : SolidDynamics3dModel(dynamics3d::kObject) {}
};
class CylinderModel : public SolidDynamics3dModel {
 public:
  CylinderModel() : SolidDynamics3dModel(dynamics3d::kObject) {}
};
class CubeModel : public SolidDynamics3dModel {
 public:
  CubeModel() : SolidDynamics3dModel(dynamics3d::kCube) {}
};

// Each pocket's body is kept where the space has the pocket, at rest.
class PocketModel : public Dynamics3dModel {
 public:
  void Add(Engine& engine, uint32_t s) override {
    engine.AddSolid(s, dynamics3d::kObject);
    dBodySetKinematic(engine.BodyOf(s));
    slots_.push_back(s);
  }
  void Remove(Engine&, uint32_t s) override {
    slots_.erase(std::find(slots_.begin(), slots_.end(), s));
  }
  void BeforeStep(Engine& engine, double) override {
    const Space& space = engine.entities();
    for (uint32_t s : slots_) {
      const Pose& pose = space.pose(s);
      const dBodyID body = engine.BodyOf(s);
      dynamics3d::PlaceBody(
          body, pose.position + pose.orientation * Vec3(0, 0, 0.5 * space.geometry(s).height()),
          pose.orientation);
      dynamics3d::SetBodyVelocity(body, Vec3::Zero(), Vec3::Zero());
    }
  }

 private:
  std::vector<uint32_t> slots_;  // in the order they came
};

COLONY_REGISTER_PHYSICS_MODEL(BoxModel, "dynamics3d:box",
                              "box: a body of its mass if movable, static geometry otherwise",
                              (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(
    CylinderModel, "dynamics3d:cylinder",
    "upright cylinder: a body of its mass if movable, static geometry otherwise",
    (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(CylinderModel, "dynamics3d:landmark",
                              "landmark: static upright cylinder", (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(
    PocketModel, "dynamics3d:pocket",
    "pocket: a kinematic box robots stop at and cannot push, where the space (the heap model) "
    "puts it",
    (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(
    CubeModel, "dynamics3d:cube",
    "construction cube: held by the manipulator's magnet; self-aligns and bonds when "
    "it lands on another cube within the capture tolerance",
    (std::vector<std::string>{}));

}  // namespace
}  // namespace colony
