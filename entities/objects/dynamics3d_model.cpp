// Boxes, cylinders and construction cubes in dynamics3d
// (engines/dynamics3d): a solid body of the entity's geometry and mass if
// movable, static geometry otherwise. Cubes are the engine's construction
// cubes: magnets hold them, and one landing on another bonds to it.
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

COLONY_REGISTER_PHYSICS_MODEL(BoxModel, "dynamics3d:box",
                              "box: a body of its mass if movable, static geometry otherwise",
                              (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(
    CylinderModel, "dynamics3d:cylinder",
    "upright cylinder: a body of its mass if movable, static geometry otherwise",
    (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(
    CubeModel, "dynamics3d:cube",
    "construction cube: held by the manipulator's magnet; self-aligns and bonds when "
    "it lands on another cube within the capture tolerance",
    (std::vector<std::string>{}));

}  // namespace
}  // namespace colony
